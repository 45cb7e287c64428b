// Nothing in the environment or the working folder changes where a participant's DDS goes: a
// process started with one of Fast DDS's overrides (environment_guard.hpp) refuses to join and
// names it, and runs once it is gone. The programs run as child processes (the overrides are
// read by the library's process-wide state).
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "child_process.hpp"

namespace nav::dds {
namespace {

/// navtool record for a moment on domain 123, started by `shell_command_prefix` (the shell's
/// environment assignments or a cd); its exit code and output.
std::pair<std::optional<int>, std::string> record_briefly(const std::string& shell_command_prefix) {
  const std::string out = ::testing::TempDir() + "environment_" + std::to_string(getpid()) + ".navrec";
  const std::string log = ::testing::TempDir() + "environment_" + std::to_string(getpid()) + ".log";
  nav::testing::ChildProcess tool({"/bin/sh", "-c",
                                   shell_command_prefix + " exec " + NAV_BIN_DIR + "/navtool record --out " + out +
                                       " --duration-s 0.2 --domain 123"},
                                  log);
  const std::optional<int> exit_code = tool.wait(std::chrono::seconds(60));
  std::remove(out.c_str());
  return {exit_code, tool.log()};
}

TEST(DdsEnvironment, EnvironmentOverridesOfFastDdsAreRefusedByName) {
  for (const char* variable : {"ROS_DISCOVERY_SERVER", "FASTDDS_ENVIRONMENT_FILE", "FASTRTPS_DEFAULT_PROFILES_FILE"}) {
    const auto [exit_code, output] = record_briefly(std::string(variable) + "=192.0.2.7:11811");
    EXPECT_EQ(exit_code, 2) << variable << ": " << output;
    EXPECT_NE(output.find(std::string(variable) + " is set ('192.0.2.7:11811')"), std::string::npos) << output;
  }
  const auto [clean_exit, clean_output] = record_briefly("");
  EXPECT_EQ(clean_exit, 0) << clean_output;
}

TEST(DdsEnvironment, AProfileFileInTheWorkingFolderIsRefusedUnlessSkipped) {
  const std::filesystem::path folder = ::testing::TempDir() + "profiles_" + std::to_string(getpid());
  std::filesystem::create_directories(folder);
  std::ofstream(folder / "DEFAULT_FASTRTPS_PROFILES.xml") << "<profiles/>\n";
  const auto [exit_code, output] = record_briefly("cd " + folder.string() + " &&");
  EXPECT_EQ(exit_code, 2) << output;
  EXPECT_NE(output.find("DEFAULT_FASTRTPS_PROFILES.xml"), std::string::npos) << output;
  // Fast DDS's own switch to skip that file is honoured.
  const auto [skipped_exit, skipped_output] = record_briefly("cd " + folder.string() + " && SKIP_DEFAULT_XML_FILE=1");
  EXPECT_EQ(skipped_exit, 0) << skipped_output;
  std::filesystem::remove_all(folder);
}

}  // namespace
}  // namespace nav::dds
