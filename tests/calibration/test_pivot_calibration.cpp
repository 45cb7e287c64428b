// Pivot calibration against synthetic truth: tip error <= 0.1 mm with 0.05 mm marker noise,
// outliers rejected, and degenerate pose sets refused with a clear error.
#include <gtest/gtest.h>

#include <cstdio>

#include "calibration_truth.hpp"
#include "nav/calibration/pivot_calibration.hpp"

namespace nav::calibration {
namespace {

using namespace nav::calibration::testing;

const Eigen::Vector3d kTipInMarker_m{0.012, -0.004, 0.161};
const Eigen::Vector3d kPivot_m{0.05, -0.02, -1.2};

/// Marker poses swung about the pivot within `max_angle_rad`, with isotropic marker noise.
std::vector<Transform> pivot_poses(std::mt19937_64& rng, std::size_t count, double max_angle_rad, double noise_m) {
  std::vector<Transform> poses;
  for (std::size_t i = 0; i < count; ++i) {
    const Eigen::Matrix3d rotation = random_rotation(rng, max_angle_rad);
    // R t_tip + p = pivot  =>  p = pivot - R t_tip
    poses.push_back(transform(rotation, kPivot_m - rotation * kTipInMarker_m + gaussian_vector(rng, noise_m)));
  }
  return poses;
}

TEST(PivotCalibration, TipWithinATenthOfAMillimetreAtFiftyMicronsOfNoise) {
  std::mt19937_64 rng(7);
  auto result = pivot_calibration(pivot_poses(rng, 200, 0.5, 0.05e-3));
  ASSERT_TRUE(result.ok()) << result.error().describe();
  const double tip_error_m = (result.value().tip_in_marker_m - kTipInMarker_m).norm();
  const double pivot_error_m = (result.value().pivot_in_tracker_m - kPivot_m).norm();
  std::printf("pivot: tip error %.4f mm, pivot error %.4f mm, RMS residual %.4f mm, spread %.1f deg, cond %.1f\n",
              tip_error_m * 1e3, pivot_error_m * 1e3, result.value().rms_residual_m * 1e3,
              result.value().angular_spread_rad * 180.0 / M_PI, result.value().condition_number);
  EXPECT_LE(tip_error_m, 0.1e-3);
  EXPECT_LE(pivot_error_m, 0.1e-3);
  // The residual of a 3-D Gaussian of sigma 0.05 mm per axis has RMS sqrt(3) * 0.05 mm.
  EXPECT_NEAR(result.value().rms_residual_m, std::sqrt(3.0) * 0.05e-3, 0.015e-3);
}

TEST(PivotCalibration, OutliersAreRejected) {
  std::mt19937_64 rng(8);
  std::vector<Transform> poses = pivot_poses(rng, 100, 0.5, 0.05e-3);
  for (std::size_t i = 0; i < 100; i += 20) poses[i].translation() += Eigen::Vector3d(0.004, 0.0, -0.003);
  auto result = pivot_calibration(poses);
  ASSERT_TRUE(result.ok()) << result.error().describe();
  EXPECT_EQ(result.value().outliers, 5u);
  EXPECT_LE((result.value().tip_in_marker_m - kTipInMarker_m).norm(), 0.1e-3);
}

TEST(PivotCalibration, DegenerateSetsAreRefused) {
  std::mt19937_64 rng(9);
  auto few = pivot_calibration(pivot_poses(rng, 5, 0.5, 0.0));
  ASSERT_FALSE(few.ok());
  EXPECT_NE(few.error().message.find("too few poses"), std::string::npos);

  auto still = pivot_calibration(pivot_poses(rng, 50, 0.01, 0.05e-3));
  ASSERT_FALSE(still.ok());
  EXPECT_NE(still.error().message.find("not enough rotation"), std::string::npos);

  std::vector<Transform> one_axis;  // turning about z only: the tip's z is undetermined
  for (int i = 0; i < 40; ++i) {
    const Eigen::Matrix3d rotation = Eigen::AngleAxisd(0.05 * i, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    one_axis.push_back(transform(rotation, kPivot_m - rotation * kTipInMarker_m));
  }
  auto axis = pivot_calibration(one_axis);
  ASSERT_FALSE(axis.ok());
  EXPECT_NE(axis.error().message.find("one axis"), std::string::npos);
}

}  // namespace
}  // namespace nav::calibration
