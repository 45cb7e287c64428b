// The AprilTag tracker on frames read through OpenCV's capture: tags rendered at known poses
// (30 cm, 640x480) are written as a PNG image sequence, read back by CaptureSource (as a
// camera's frames would be) and tracked: every pose within 1 mm and 1 degree, in order.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <vector>

#include "nav/core/clock.hpp"
#include "nav/trackers/apriltag_tracker.hpp"
#include "nav/ultrasound/capture_source.hpp"
#include "support/test_data.hpp"
#include "trackers/apriltag_test_camera.hpp"

namespace nav::trackers {
namespace {

using testing::kCamera;
using testing::kTagSize_m;

Eigen::Isometry3d tag_pose(double angle_rad, const Eigen::Vector3d& t_m) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = Eigen::AngleAxisd(angle_rad, Eigen::Vector3d(1.0, -0.5, 0.3).normalized()).toRotationMatrix();
  pose.translation() = t_m;
  return pose;
}

TEST(AprilTagCapture, TagsReadThroughTheCaptureAreTrackedWithinAMillimetreAndADegree) {
  const std::filesystem::path folder = nav::testing::temporary_path("apriltag_capture");
  std::filesystem::remove_all(folder);
  std::filesystem::create_directories(folder);
  std::vector<Eigen::Isometry3d> truths;
  for (int i = 0; i < 4; ++i) {
    truths.push_back(tag_pose(0.3 + 0.15 * i, {-0.02 + 0.013 * i, 0.01 - 0.007 * i, 0.30}));
    const GrayImage image =
        render_tags({{5, truths.back()}}, kTagSize_m, kCamera, 640, 480, 2.0, 31 + static_cast<std::uint64_t>(i));
    cv::Mat mat(image.height_px, image.width_px, CV_8UC1, const_cast<std::uint8_t*>(image.pixels.data()));
    char name[32];
    std::snprintf(name, sizeof name, "frame_%04d.png", i);
    ASSERT_TRUE(cv::imwrite((folder / name).string(), mat));
  }
  SimulatedClock clock(0);
  auto capture = ultrasound::CaptureSource::open((folder / "frame_%04d.png").string(), {}, clock);
  ASSERT_TRUE(capture.ok()) << capture.error().describe();
  auto tracker = AprilTagTracker::create(kCamera, kTagSize_m, {});
  ASSERT_TRUE(tracker.ok());
  auto frame = std::make_unique<dds::UltrasoundFrame>();
  std::size_t frames = 0;
  for (;;) {
    const Result<bool> more = capture.value()->next(*frame);
    ASSERT_TRUE(more.ok()) << more.error().describe();
    if (!more.value()) break;
    ASSERT_LT(frames, truths.size());
    const GrayImage image = gray_image_from_frame(*frame);
    ASSERT_EQ(image.width_px, 640);
    ASSERT_EQ(image.height_px, 480);
    const std::vector<TagObservation> seen = tracker.value()->detect(image);
    ASSERT_EQ(seen.size(), 1u);
    EXPECT_EQ(seen[0].id, 5);
    const Eigen::Isometry3d& truth = truths[frames];
    const double translation_m = (seen[0].camera_from_tag.translation() - truth.translation()).norm();
    const double rotation_deg =
        Eigen::AngleAxisd(seen[0].camera_from_tag.rotation().transpose() * truth.rotation()).angle() * 180.0 / M_PI;
    std::printf("frame %zu through the capture: %.3f mm, %.3f deg\n", frames, 1e3 * translation_m, rotation_deg);
    EXPECT_LT(translation_m, 1e-3);
    EXPECT_LT(rotation_deg, 1.0);
    ++frames;
  }
  EXPECT_EQ(frames, truths.size());
  std::filesystem::remove_all(folder);
}

}  // namespace
}  // namespace nav::trackers
