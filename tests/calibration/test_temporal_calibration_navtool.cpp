// navtool calib temporal end to end on the real water-tank recordings: the lag and its
// uncertainty printed and written; a search window too narrow for the lag is a clear error.
#include <gtest/gtest.h>

#include "support/run_command.hpp"
#include "support/test_data.hpp"

namespace nav::calibration {
namespace {

using nav::testing::executable_path;
using nav::testing::file_text;
using nav::testing::run_command;
using nav::testing::shared_data_path;

TEST(NavtoolCalibTemporal, WaterTankLagWrittenAndNarrowWindowRefused) {
  const std::string video = shared_data_path("plus/WaterTankBottomTranslationVideoBuffer.igs.mha");
  const std::string tracker = shared_data_path("plus/WaterTankBottomTranslationTrackerBuffer.igs.mha");
  NAV_REQUIRE_SHARED_DATA(video);
  NAV_REQUIRE_SHARED_DATA(tracker);
  const std::string out = nav::testing::temporary_path("calib_temporal_lag.txt");
  const std::string command = executable_path("navtool") + " calib temporal --video " + video + " --tracker " + tracker;
  const auto run = run_command(command + " --out " + out + " 2>&1");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const std::string text = file_text(out);
  EXPECT_NE(text.find("video_lag_s = 0.06"), std::string::npos) << text;  // about 67 ms
  EXPECT_NE(text.find("uncertainty_s = "), std::string::npos);
  const auto narrow = run_command(command + " --max-lag-s 0.03 2>&1");
  EXPECT_EQ(narrow.exit_code, 2);
  EXPECT_NE(narrow.output.find("beyond the search window"), std::string::npos) << narrow.output;
}

}  // namespace
}  // namespace nav::calibration
