#pragma once
// Lens distortion of a pinhole camera, Brown-Conrady in OpenCV's convention: a point of the
// normalised image plane (x, y) = (X/Z, Y/Z) is seen at
//   x_d = x (1 + k1 r^2 + k2 r^4 + k3 r^6) + 2 p1 x y + p2 (r^2 + 2 x^2)
//   y_d = y (1 + k1 r^2 + k2 r^4 + k3 r^6) + p1 (r^2 + 2 y^2) + 2 p2 x y,   r^2 = x^2 + y^2,
// then in pixels (fx x_d + cx, fy y_d + cy). Header-light (Eigen core only).
#include <Eigen/Core>

namespace nav::calibration {

/// Radial (k1, k2, k3) and tangential (p1, p2) coefficients; all zero is no distortion.
struct LensDistortion {
  double k1 = 0.0;
  double k2 = 0.0;
  double p1 = 0.0;
  double p2 = 0.0;
  double k3 = 0.0;

  bool is_zero() const noexcept { return k1 == 0.0 && k2 == 0.0 && p1 == 0.0 && p2 == 0.0 && k3 == 0.0; }
};

/// Where the lens puts the normalised point `ideal` (the formula above).
Eigen::Vector2d distort(const LensDistortion& lens, const Eigen::Vector2d& ideal) noexcept;

/// The normalised point the lens put at `distorted`: a fixed number of fixed-point
/// iterations (as OpenCV's undistortPoints), exact to < 1e-9 for the distortions of real
/// lenses within their field of view.
Eigen::Vector2d undistort(const LensDistortion& lens, const Eigen::Vector2d& distorted) noexcept;

}  // namespace nav::calibration
