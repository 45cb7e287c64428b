// navbench dds runs end to end, child process included, and writes its latency table as
// JSON with every measurement received, within generous budgets (a loaded host; the project's
// own targets, 200 us and 2 ms at p99 across processes, are reported in targets_met).
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
  for (const char* name :
       {"\"pose_in_process\"", "\"pose_cross_process\"", "\"frame_1mib_cross_process\"",
        "\"frame_1mib_cross_process_no_data_sharing\"", "\"frame_1mib_throughput_cross_process\"", "\"targets_met\""}) {
    EXPECT_NE(json.find(name), std::string::npos) << name;
  }
  EXPECT_EQ(json.find("\"received\": 0,"), std::string::npos) << "a measurement received nothing:\n" << json;
  // The latency measurements (not the throughput ones, which may drop by design): nearly every
  // sample received, median and p99 within budgets a loaded host keeps.
  struct Budget {
    const char* name;
    double median_us, p99_us;
  };
  for (const Budget& b :
       {Budget{"pose_in_process", 2'000, 20'000}, Budget{"pose_cross_process", 2'000, 20'000},
        Budget{"frame_1mib_in_process", 10'000, 100'000}, Budget{"frame_1mib_cross_process", 10'000, 100'000}}) {
    const std::size_t at = json.find(std::string("\"name\": \"") + b.name + "\"");
    ASSERT_NE(at, std::string::npos) << b.name;
    const std::string line = json.substr(at, json.find('\n', at) - at);
    std::printf("%s\n", line.c_str());
    EXPECT_GE(nav::testing::number_after(line, "\"received\": "), 0.9 * nav::testing::number_after(line, "\"sent\": "))
        << b.name;
    EXPECT_LE(nav::testing::number_after(line, "\"median_us\": "), b.median_us) << b.name;
    EXPECT_LE(nav::testing::number_after(line, "\"p99_us\": "), b.p99_us) << b.name;
  }
}

TEST(DdsNavbench, RefusesAMissingJsonPath) {
  const std::string command = std::string(NAV_BIN_DIR) + "/navbench dds --pose-samples 10 2>/dev/null";
  const int status = std::system(command.c_str());
  ASSERT_TRUE(WIFEXITED(status));
  EXPECT_EQ(WEXITSTATUS(status), 2);
}

}  // namespace
