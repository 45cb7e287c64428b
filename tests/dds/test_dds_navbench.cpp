// navbench dds runs end to end, child process included, and writes its latency table as
// JSON with every measurement received. (Figures are printed by navbench, not asserted.)
#include <gtest/gtest.h>

#include <sys/wait.h>

#include <cstdio>
#include <cstdlib>
#include <string>

#include "support/test_data.hpp"

namespace {

TEST(DdsNavbench, WritesTheLatencyTableAsJson) {
  const std::string json_path = ::testing::TempDir() + "navbench_dds_test.json";
  std::remove(json_path.c_str());
  const std::string command = std::string(NAV_BIN_DIR) + "/navbench dds --json " + json_path +
                              " --domain 150 --pose-samples 200 --frame-samples 20";
  ASSERT_EQ(std::system(command.c_str()), 0) << command;
  ASSERT_TRUE(nav::testing::file_exists(json_path));
  const std::string json = nav::testing::file_text(json_path);
  for (const char* name : {"\"pose_in_process\"", "\"pose_cross_process\"", "\"frame_1mib_cross_process\"",
                           "\"frame_1mib_cross_process_no_data_sharing\"", "\"frame_1mib_throughput_cross_process\"",
                           "\"targets_met\""}) {
    EXPECT_NE(json.find(name), std::string::npos) << name;
  }
  EXPECT_EQ(json.find("\"received\": 0,"), std::string::npos) << "a measurement received nothing:\n" << json;
}

TEST(DdsNavbench, RefusesAMissingJsonPath) {
  const std::string command = std::string(NAV_BIN_DIR) + "/navbench dds --pose-samples 10 2>/dev/null";
  const int status = std::system(command.c_str());
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 2);
}

}  // namespace
