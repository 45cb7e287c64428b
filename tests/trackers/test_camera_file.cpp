// The camera intrinsics file of navtool calib camera read back: the numbers it writes, and
// every broken file refused with its name and line (missing, too few numbers, a non-finite
// one, a focal length that is not positive, comments only).
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "nav/trackers/camera_file.hpp"
#include "support/test_data.hpp"

namespace nav::trackers {
namespace {

std::string file_with(const std::string& name, const std::string& text) {
  const std::string path = testing::temporary_path(name);
  std::ofstream(path) << text;
  return path;
}

TEST(CameraFile, ReadsTheNumbersNavtoolCalibCameraWrites) {
  const std::string path = file_with("camera_ok.txt",
                                     "# fx_px fy_px cx_px cy_px k1 k2 p1 p2 k3 rms_px\n"
                                     "612.5 610.25 320.5 240.75 -0.1 0.02 0.001 -0.002 0.003 0.12\n");
  const auto camera = read_camera_intrinsics(path);
  ASSERT_TRUE(camera.ok()) << camera.error().describe();
  EXPECT_EQ(camera.value().fx_px, 612.5);
  EXPECT_EQ(camera.value().fy_px, 610.25);
  EXPECT_EQ(camera.value().cx_px, 320.5);
  EXPECT_EQ(camera.value().cy_px, 240.75);
  EXPECT_EQ(camera.value().distortion.k1, -0.1);
  EXPECT_EQ(camera.value().distortion.p2, -0.002);
  EXPECT_EQ(camera.value().distortion.k3, 0.003);
}

TEST(CameraFile, BrokenFilesAreRefusedWithTheirNameAndLine) {
  const std::string missing = testing::temporary_path("no_such_camera.txt");
  const auto absent = read_camera_intrinsics(missing);
  ASSERT_FALSE(absent.ok());
  EXPECT_EQ(absent.error().file, missing);
  struct Case {
    const char* name;
    const char* text;
    int line;
    const char* says;
  };
  for (const Case& c :
       {Case{"camera_short.txt", "# header\n600 600 319.5\n", 2, "nine finite numbers"},
        Case{"camera_nan.txt", "# header\n\n600 600 319.5 239.5 nan 0 0 0 0 0.1\n", 3, "nine finite numbers"},
        Case{"camera_word.txt", "600 600 319.5 239.5 0 0 zero 0 0 0.1\n", 1, "nine finite numbers"},
        Case{"camera_focal.txt", "# header\n0 600 319.5 239.5 0 0 0 0 0 0.1\n", 2, "must be positive"},
        Case{"camera_comments.txt", "# header\n# nothing else\n", 2, "no intrinsics line"}}) {
    const std::string path = file_with(c.name, c.text);
    const auto refused = read_camera_intrinsics(path);
    ASSERT_FALSE(refused.ok()) << c.name;
    EXPECT_EQ(refused.error().file, path) << c.name;
    EXPECT_EQ(refused.error().line, c.line) << c.name << ": " << refused.error().describe();
    EXPECT_NE(refused.error().message.find(c.says), std::string::npos) << c.name << ": " << refused.error().describe();
  }
}

}  // namespace
}  // namespace nav::trackers
