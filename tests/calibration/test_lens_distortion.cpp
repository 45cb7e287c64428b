// The Brown-Conrady lens model against hand-computed values (OpenCV's formula), and its
// undistortion against the distortion it inverts.
#include <gtest/gtest.h>

#include "nav/calibration/lens_distortion.hpp"

namespace nav::calibration {
namespace {

TEST(LensDistortion, MatchesTheFormulaByHand) {
  const LensDistortion lens{-0.2, 0.05, 0.001, -0.002, 0.01};
  const double x = 0.3, y = -0.2, r2 = 0.13;
  const double radial = 1.0 - 0.2 * r2 + 0.05 * r2 * r2 + 0.01 * r2 * r2 * r2;
  const Eigen::Vector2d seen = distort(lens, {x, y});
  EXPECT_NEAR(seen.x(), x * radial + 2 * 0.001 * x * y - 0.002 * (r2 + 2 * x * x), 1e-15);
  EXPECT_NEAR(seen.y(), y * radial + 0.001 * (r2 + 2 * y * y) + 2 * -0.002 * x * y, 1e-15);
  EXPECT_EQ(distort(LensDistortion{}, {x, y}), Eigen::Vector2d(x, y));
  EXPECT_TRUE(LensDistortion{}.is_zero());
  EXPECT_FALSE(lens.is_zero());
}

TEST(LensDistortion, UndistortInvertsDistortOverTheFieldOfView) {
  // A 640 x 480 camera with f = 600 px sees up to |x| < 0.55, |y| < 0.42 (normalised).
  const LensDistortion lens{-0.25, 0.08, 0.0012, -0.0009, 0.0};
  double worst = 0.0;
  for (double x = -0.7; x <= 0.7; x += 0.05) {
    for (double y = -0.55; y <= 0.55; y += 0.05) {
      const Eigen::Vector2d ideal(x, y);
      worst = std::max(worst, (undistort(lens, distort(lens, ideal)) - ideal).norm());
    }
  }
  EXPECT_LT(worst, 1e-9);
}

}  // namespace
}  // namespace nav::calibration
