#include "nav/station/security_roles.hpp"

namespace nav::station {
namespace {

/// `path` with every "{role}" replaced by `role`.
std::string with_role(std::string path, const std::string& role) {
  static constexpr std::string_view kPlaceholder = "{role}";
  for (std::size_t at = path.find(kPlaceholder); at != std::string::npos;
       at = path.find(kPlaceholder, at + role.size()))
    path.replace(at, kPlaceholder.size(), role);
  return path;
}

}  // namespace

const char* role_name(Role role) {
  switch (role) {
    case Role::station:
      return "station";
    case Role::devices:
      return "devices";
    case Role::display:
      return "display";
    case Role::tool:
      return "tool";
  }
  return "station";
}

RoleTopics role_topics(Role role) {
  using dds::Topic;
  const std::vector<Topic> all{Topic::tool_pose,         Topic::ultrasound_frame, Topic::needle_state,
                               Topic::target_prediction, Topic::deformed_surface, Topic::station_health,
                               Topic::ground_truth,      Topic::needle_force};
  switch (role) {
    case Role::station:
      return {{Topic::needle_state, Topic::target_prediction, Topic::deformed_surface, Topic::station_health,
               Topic::needle_force},
              {Topic::tool_pose, Topic::ultrasound_frame}};
    case Role::devices:
      return {{Topic::tool_pose, Topic::ultrasound_frame, Topic::ground_truth}, {Topic::station_health}};
    case Role::display:
      return {{}, all};
    case Role::tool:
      return {all, all};
  }
  return {};
}

SecuritySettings security_folder(const std::string& dir) {
  SecuritySettings s;
  s.ca = dir + "/ca.pem";
  s.certificate = dir + "/{role}/certificate.pem";
  s.private_key = dir + "/{role}/private_key.pem";
  s.governance = dir + "/governance.p7s";
  s.permissions = dir + "/{role}/permissions.p7s";
  return s;
}

dds::SecurityFiles security_files(const SecuritySettings& security, Role role) {
  const std::string name = role_name(role);
  return {with_role(security.ca, name), with_role(security.certificate, name), with_role(security.private_key, name),
          with_role(security.governance, name), with_role(security.permissions, name)};
}

}  // namespace nav::station
