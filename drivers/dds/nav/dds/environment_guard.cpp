#include "nav/dds/environment_guard.hpp"

#include <cstdlib>
#include <filesystem>
#include <string>

namespace nav::dds {

Status refuse_environment_overrides() {
  struct Override {
    const char* variable;
    const char* effect;
  };
  static constexpr Override kOverrides[] = {
      {"ROS_DISCOVERY_SERVER", "would make every participant a discovery client of the servers it lists"},
      {"FASTDDS_ENVIRONMENT_FILE",
       "names a file whose ROS_DISCOVERY_SERVER would make every participant a discovery client"},
      {"FASTRTPS_DEFAULT_PROFILES_FILE",
       "would load XML defaults and library settings outside the code's network settings"},
  };
  for (const Override& o : kOverrides) {
    const char* value = std::getenv(o.variable);
    if (value == nullptr) continue;
    return Error{
        .message = std::string(o.variable) + " is set ('" + value + "'): Fast DDS " + o.effect +
                   "; unset it (a participant's network comes from its settings: local address, peers, and an XML "
                   "profile named there)",
        .field = o.variable};
  }
  const char* skip = std::getenv("SKIP_DEFAULT_XML_FILE");
  std::error_code ignored;
  if ((skip == nullptr || skip[0] != '1') && std::filesystem::exists("DEFAULT_FASTRTPS_PROFILES.xml", ignored)) {
    return Error{.message =
                     "Fast DDS would load this file from the working folder (XML defaults and library settings outside "
                     "the code's network settings); remove it, run elsewhere, or set SKIP_DEFAULT_XML_FILE=1",
                 .file = std::filesystem::absolute("DEFAULT_FASTRTPS_PROFILES.xml", ignored).string()};
  }
  return Done{};
}

}  // namespace nav::dds
