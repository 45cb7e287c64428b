// The AprilTag optical tracker on synthetic renderings (640x480, f = 600 px): single tags at
// 30 cm within 1 mm and 1 degree, corners at integer pixel centres within 0.5 px, a
// multi-tag rigid body from all its corners, an image folder source, a body out of view
// reported missing.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>

#include "nav/trackers/apriltag_tracker.hpp"
#include "support/test_data.hpp"
#include "trackers/apriltag_test_camera.hpp"

namespace nav::trackers {
namespace {

using testing::kCamera;
using testing::kTagSize_m;

Eigen::Isometry3d pose_deg(double rx, double ry, double rz, const Eigen::Vector3d& t_m) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = (Eigen::AngleAxisd(rx * M_PI / 180.0, Eigen::Vector3d::UnitX()) *
                   Eigen::AngleAxisd(ry * M_PI / 180.0, Eigen::Vector3d::UnitY()) *
                   Eigen::AngleAxisd(rz * M_PI / 180.0, Eigen::Vector3d::UnitZ()))
                      .toRotationMatrix();
  pose.translation() = t_m;
  return pose;
}

double angle_deg(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) {
  return Eigen::AngleAxisd(a.rotation().transpose() * b.rotation()).angle() * 180.0 / M_PI;
}

std::unique_ptr<AprilTagTracker> make_tracker(std::vector<TagBody> bodies = {}) {
  auto tracker = AprilTagTracker::create(kCamera, kTagSize_m, std::move(bodies));
  EXPECT_TRUE(tracker.ok());
  return std::move(tracker).value();
}

TEST(AprilTagTracker, SingleTagPoseWithinAMillimetreAndADegreeAt30cm) {
  const auto tracker = make_tracker();
  const std::vector<Eigen::Isometry3d> truths{pose_deg(25, -20, 10, {0.01, -0.02, 0.30}),
                                              pose_deg(-35, 15, 120, {-0.03, 0.01, 0.30}),
                                              pose_deg(10, 40, 200, {0.0, 0.03, 0.30})};
  for (std::size_t i = 0; i < truths.size(); ++i) {
    const int id = static_cast<int>(7 + 100 * i);
    const GrayImage image = render_tags({{id, truths[i]}}, kTagSize_m, kCamera, 640, 480, 2.0, 11 + i);
    const std::vector<TagObservation> seen = tracker->detect(image);
    ASSERT_EQ(seen.size(), 1u);
    EXPECT_EQ(seen[0].id, id);
    EXPECT_EQ(seen[0].hamming, 0);
    double corner_error_px = 0.0;
    for (int k = 0; k < 4; ++k) {
      const Eigen::Vector3d p = truths[i] * tag_corner(k, kTagSize_m);
      const Eigen::Vector2d expected(kCamera.fx_px * p.x() / p.z() + kCamera.cx_px,
                                     kCamera.fy_px * p.y() / p.z() + kCamera.cy_px);
      corner_error_px = std::max(corner_error_px, (seen[0].corners_px[k] - expected).norm());
    }
    const double translation_error_m = (seen[0].camera_from_tag.translation() - truths[i].translation()).norm();
    const double rotation_error_deg = angle_deg(seen[0].camera_from_tag, truths[i]);
    std::printf("tag %d at 30 cm: corner error %.3f px, translation %.3f mm, rotation %.3f deg\n", id, corner_error_px,
                translation_error_m * 1e3, rotation_error_deg);
    EXPECT_LT(corner_error_px, 0.5);
    EXPECT_LT(translation_error_m, 1e-3);
    EXPECT_LT(rotation_error_deg, 1.0);
  }
}

TEST(AprilTagTracker, MultiTagBodyFromAllCorners) {
  // Four tags on a 12 cm plate, body frame at the plate's centre.
  TagBody plate{3, {}};
  for (int i = 0; i < 4; ++i) {
    Eigen::Isometry3d body_from_tag = Eigen::Isometry3d::Identity();
    body_from_tag.translation() = Eigen::Vector3d((i % 2 == 0 ? -0.035 : 0.035), (i < 2 ? -0.035 : 0.035), 0.0);
    plate.tags.push_back({20 + i, body_from_tag});
  }
  const auto tracker = make_tracker({plate, TagBody{4, {{99, Eigen::Isometry3d::Identity()}}}});
  const Eigen::Isometry3d truth = pose_deg(20, -25, 30, {0.02, 0.01, 0.45});
  std::vector<TagRendering> rendering;
  for (const BodyTag& tag : plate.tags) rendering.push_back({tag.id, truth * tag.body_from_tag});
  const GrayImage image = render_tags(rendering, kTagSize_m, kCamera, 640, 480, 2.0, 21);
  const std::vector<TrackerSample> samples = tracker->track(image, 1234);
  ASSERT_EQ(samples.size(), 2u);
  ASSERT_EQ(samples[0].state, ToolState::ok);
  EXPECT_EQ(samples[0].measured_time_ns, 1234);
  const Eigen::Quaterniond q(samples[0].orientation_wxyz[0], samples[0].orientation_wxyz[1],
                             samples[0].orientation_wxyz[2], samples[0].orientation_wxyz[3]);
  Eigen::Isometry3d measured = Eigen::Isometry3d::Identity();
  measured.linear() = q.toRotationMatrix();
  measured.translation() =
      Eigen::Vector3d(samples[0].position_m[0], samples[0].position_m[1], samples[0].position_m[2]);
  const double translation_error_m = (measured.translation() - truth.translation()).norm();
  std::printf("4-tag body at 45 cm: translation %.3f mm, rotation %.3f deg, reprojection %.3f mm\n",
              translation_error_m * 1e3, angle_deg(measured, truth), samples[0].rms_error_m * 1e3);
  EXPECT_LT(translation_error_m, 1e-3);
  EXPECT_LT(angle_deg(measured, truth), 0.5);
  EXPECT_EQ(samples[1].state, ToolState::missing);  // tag 99 is not in the frame
}

TEST(AprilTagTracker, ImageFolderSourceInNameOrder) {
  const std::string folder = nav::testing::temporary_path("apriltag_frames");
  std::filesystem::remove_all(folder);
  std::filesystem::create_directories(folder);
  const auto tracker = make_tracker({TagBody{1, {{5, Eigen::Isometry3d::Identity()}}}});
  for (int frame = 0; frame < 3; ++frame) {
    const Eigen::Isometry3d truth = pose_deg(10.0 * frame, 15, 0, {0.01 * frame, 0.0, 0.3});
    char name[64];
    std::snprintf(name, sizeof name, "/frame_%03d.pgm", frame);
    ASSERT_TRUE(
        write_pgm(folder + name, render_tags({{5, truth}}, kTagSize_m, kCamera, 640, 480, 2.0, 30 + frame)).ok());
  }
  auto files = list_pgm_files(folder);
  ASSERT_TRUE(files.ok());
  ASSERT_EQ(files.value().size(), 3u);
  for (std::size_t frame = 0; frame < 3; ++frame) {
    auto image = read_pgm(files.value()[frame]);
    ASSERT_TRUE(image.ok()) << image.error().describe();
    const std::vector<TrackerSample> samples = tracker->track(image.value(), static_cast<TimeNs>(frame));
    ASSERT_EQ(samples[0].state, ToolState::ok);
    EXPECT_NEAR(samples[0].position_m[0], 0.01 * static_cast<double>(frame), 1e-3);
  }
  EXPECT_FALSE(read_pgm(folder + "/missing.pgm").ok());
}

}  // namespace
}  // namespace nav::trackers
