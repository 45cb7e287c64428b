// The AprilTag tracker through a distorting lens (Brown-Conrady, rendered by the tag
// renderer): with the lens known the pose stays within 1 mm and 1 degree at 30 cm on
// 640x480; ignoring the lens it does not.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "nav/trackers/apriltag_tracker.hpp"
#include "trackers/apriltag_test_camera.hpp"

namespace nav::trackers {
namespace {

using testing::kTagSize_m;
const CameraIntrinsics kPinhole{600.0, 600.0, 319.5, 239.5};
const calibration::LensDistortion kLens{-0.25, 0.08, 0.0012, -0.0009, 0.0};

double angle_deg(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  return Eigen::AngleAxisd(a.transpose() * b).angle() * 180.0 / M_PI;
}

TEST(AprilTagDistortion, ProjectionIsThePinholeThroughTheLens) {
  CameraIntrinsics camera = kPinhole;
  camera.distortion = kLens;
  const Eigen::Vector3d point(0.08, -0.05, 0.3);
  const Eigen::Vector2d seen = project(camera, point);
  const Eigen::Vector2d lens = calibration::distort(kLens, {point.x() / point.z(), point.y() / point.z()});
  EXPECT_NEAR(seen.x(), 600.0 * lens.x() + 319.5, 1e-12);
  EXPECT_LT((undistort_pixel(camera, seen) - project(kPinhole, point)).norm(), 1e-9);
}

TEST(AprilTagDistortion, PoseAt30cmWithinAMillimetreAndADegreeOnlyWithTheLensCorrected) {
  CameraIntrinsics camera = kPinhole;
  camera.distortion = kLens;
  auto corrected = AprilTagTracker::create(camera, kTagSize_m, {});
  auto ignorant = AprilTagTracker::create(kPinhole, kTagSize_m, {});
  ASSERT_TRUE(corrected.ok() && ignorant.ok());
  // Tags towards the image's edges, where the lens moves them most, 30 cm away.
  const Eigen::Vector3d positions[] = {{0.08, 0.05, 0.3}, {-0.09, -0.04, 0.3}, {0.10, -0.06, 0.3}, {0.0, 0.0, 0.3}};
  double worst_t_mm = 0.0, worst_r_deg = 0.0, ignorant_t_mm = 0.0, ignorant_r_deg = 0.0;
  for (int i = 0; i < 4; ++i) {
    Eigen::Isometry3d truth = Eigen::Isometry3d::Identity();
    truth.linear() = Eigen::AngleAxisd(0.35, Eigen::Vector3d(1.0, -0.6, 0.3 * i).normalized()).toRotationMatrix();
    truth.translation() = positions[i];
    const GrayImage image = render_tags({{3 + i, truth}}, kTagSize_m, camera, 640, 480, 2.0, 50 + i);
    const auto seen = corrected.value()->detect(image);
    const auto naive = ignorant.value()->detect(image);
    ASSERT_EQ(seen.size(), 1u) << "tag " << i;
    ASSERT_EQ(naive.size(), 1u) << "tag " << i;
    // The corners are reported as seen: the distorted projection of the tag's corners.
    for (int k = 0; k < 4; ++k) {
      EXPECT_LT((seen[0].corners_px[k] - project(camera, truth * tag_corner(k, kTagSize_m))).norm(), 0.5)
          << "tag " << i;
    }
    const double t_mm = (seen[0].camera_from_tag.translation() - truth.translation()).norm() * 1e3;
    const double r_deg = angle_deg(seen[0].camera_from_tag.rotation(), truth.rotation());
    const double naive_t_mm = (naive[0].camera_from_tag.translation() - truth.translation()).norm() * 1e3;
    const double naive_r_deg = angle_deg(naive[0].camera_from_tag.rotation(), truth.rotation());
    std::printf("tag at (%.2f, %.2f, %.2f) m: corrected %.3f mm %.3f deg, lens ignored %.3f mm %.3f deg\n",
                positions[i].x(), positions[i].y(), positions[i].z(), t_mm, r_deg, naive_t_mm, naive_r_deg);
    worst_t_mm = std::max(worst_t_mm, t_mm);
    worst_r_deg = std::max(worst_r_deg, r_deg);
    ignorant_t_mm = std::max(ignorant_t_mm, naive_t_mm);
    ignorant_r_deg = std::max(ignorant_r_deg, naive_r_deg);
  }
  EXPECT_LT(worst_t_mm, 1.0);
  EXPECT_LT(worst_r_deg, 1.0);
  EXPECT_GT(ignorant_t_mm, 3.0);  // the lens ignored: several millimetres off
}

TEST(AprilTagDistortion, BodyPoseReprojectsThroughTheLens) {
  CameraIntrinsics camera = kPinhole;
  camera.distortion = kLens;
  Eigen::Isometry3d right = Eigen::Isometry3d::Identity();
  right.translation() = Eigen::Vector3d(0.07, 0.0, 0.0);
  const TagBody body{9, {{1, Eigen::Isometry3d::Identity()}, {2, right}}};
  auto tracker = AprilTagTracker::create(camera, kTagSize_m, {body});
  ASSERT_TRUE(tracker.ok());
  Eigen::Isometry3d truth = Eigen::Isometry3d::Identity();
  truth.linear() = Eigen::AngleAxisd(0.3, Eigen::Vector3d(0.2, 1.0, 0.1).normalized()).toRotationMatrix();
  truth.translation() = Eigen::Vector3d(0.03, 0.06, 0.3);
  const GrayImage image = render_tags({{1, truth}, {2, truth * right}}, kTagSize_m, camera, 640, 480, 2.0, 61);
  Eigen::Isometry3d pose;
  double rms_px = 0.0;
  ASSERT_TRUE(tracker.value()->body_pose(body, tracker.value()->detect(image), pose, rms_px));
  const double t_mm = (pose.translation() - truth.translation()).norm() * 1e3;
  const double r_deg = angle_deg(pose.rotation(), truth.rotation());
  std::printf("two-tag body through the lens: %.3f mm, %.3f deg, reprojection RMS %.3f px\n", t_mm, r_deg, rms_px);
  EXPECT_LT(t_mm, 1.0);
  EXPECT_LT(r_deg, 1.0);
  EXPECT_LT(rms_px, 0.5);
}

}  // namespace
}  // namespace nav::trackers
