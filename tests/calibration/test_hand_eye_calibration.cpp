// Hand-eye calibration AX = XB against synthetic truth with seeded pose noise, and the
// degenerate cases (too few poses, rotations about one axis).
#include <gtest/gtest.h>

#include <cstdio>

#include "calibration_truth.hpp"
#include "nav/calibration/hand_eye_calibration.hpp"

namespace nav::calibration {
namespace {

using namespace nav::calibration::testing;

struct PoseLists {
  std::vector<Transform> tracker_from_marker;
  std::vector<Transform> camera_from_target;
};

/// Poses of a camera on a tracked marker viewing a fixed target; noise on both sides.
PoseLists hand_eye_poses(std::mt19937_64& rng, const Transform& marker_from_camera, std::size_t count,
                         double rotation_noise_rad, double translation_noise_m) {
  const Transform tracker_from_target = transform(random_rotation(rng, 1.0), {0.1, 0.2, -1.0});
  PoseLists lists;
  for (std::size_t i = 0; i < count; ++i) {
    const Transform marker =
        transform(random_rotation(rng, 0.8), Eigen::Vector3d(0.0, 0.0, -0.6) + gaussian_vector(rng, 0.1));
    Transform camera = (marker * marker_from_camera).inverse() * tracker_from_target;
    camera.linear() = camera.linear() * random_rotation(rng, rotation_noise_rad);
    camera.translation() += gaussian_vector(rng, translation_noise_m);
    Transform noisy_marker = marker;
    noisy_marker.linear() = marker.linear() * random_rotation(rng, rotation_noise_rad);
    noisy_marker.translation() += gaussian_vector(rng, translation_noise_m);
    lists.tracker_from_marker.push_back(noisy_marker);
    lists.camera_from_target.push_back(camera);
  }
  return lists;
}

TEST(HandEyeCalibration, RecoversTheExactTransformWithoutNoise) {
  std::mt19937_64 rng(21);
  const Transform truth = transform(random_rotation(rng, 2.0), {0.03, -0.05, 0.08});
  const PoseLists lists = hand_eye_poses(rng, truth, 10, 0.0, 0.0);
  auto result = hand_eye_calibration(lists.tracker_from_marker, lists.camera_from_target);
  ASSERT_TRUE(result.ok()) << result.error().describe();
  EXPECT_TRUE(result.value().marker_from_camera.isApprox(truth, 1e-9));
  EXPECT_LT(result.value().rms_translation_residual_m, 1e-9);
}

TEST(HandEyeCalibration, ErrorsStaySmallWithPoseNoise) {
  std::mt19937_64 rng(22);
  const Transform truth = transform(random_rotation(rng, 2.0), {0.03, -0.05, 0.08});
  // 0.1 degree and 0.2 mm of noise on every pose, 20 stations.
  const PoseLists lists = hand_eye_poses(rng, truth, 20, 0.1 * M_PI / 180.0, 0.2e-3);
  auto result = hand_eye_calibration(lists.tracker_from_marker, lists.camera_from_target);
  ASSERT_TRUE(result.ok()) << result.error().describe();
  const double rotation_error_deg =
      rotation_angle_rad(result.value().marker_from_camera.rotation(), truth.rotation()) * 180.0 / M_PI;
  const double translation_error_m = (result.value().marker_from_camera.translation() - truth.translation()).norm();
  std::printf("hand-eye: rotation error %.4f deg, translation error %.3f mm (0.1 deg / 0.2 mm pose noise)\n",
              rotation_error_deg, translation_error_m * 1e3);
  EXPECT_LT(rotation_error_deg, 0.1);
  EXPECT_LT(translation_error_m, 1.0e-3);
}

TEST(HandEyeCalibration, DegenerateMotionsAreRefused) {
  std::vector<Transform> two(2, Transform::Identity());
  EXPECT_FALSE(hand_eye_calibration(two, two).ok());
  std::vector<Transform> markers, cameras;  // every motion about the z axis
  for (int i = 0; i < 6; ++i) {
    markers.push_back(
        transform(Eigen::AngleAxisd(0.3 * i, Eigen::Vector3d::UnitZ()).toRotationMatrix(), {0.01 * i, 0, 0}));
    cameras.push_back(markers.back().inverse());
  }
  auto parallel = hand_eye_calibration(markers, cameras);
  ASSERT_FALSE(parallel.ok());
  EXPECT_NE(parallel.error().message.find("parallel"), std::string::npos);
}

}  // namespace
}  // namespace nav::calibration
