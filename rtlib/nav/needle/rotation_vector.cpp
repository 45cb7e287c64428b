#include "nav/needle/rotation_vector.hpp"

#include <cmath>

namespace nav {

Eigen::Quaterniond quaternion_from_rotation_vector(const Eigen::Vector3d& theta_rad) noexcept {
  const double angle = theta_rad.norm();
  // sin(a/2)/a by its series below 1e-4 rad, where the closed form loses digits.
  const double half_sinc = angle < 1e-4 ? 0.5 - angle * angle / 48.0 : std::sin(0.5 * angle) / angle;
  const Eigen::Vector3d v = half_sinc * theta_rad;
  return Eigen::Quaterniond(std::cos(0.5 * angle), v.x(), v.y(), v.z());
}

Eigen::Vector3d rotation_vector_from_quaternion(const Eigen::Quaterniond& q) noexcept {
  const double sign = q.w() < 0.0 ? -1.0 : 1.0;
  const Eigen::Vector3d v = sign * q.vec();
  const double w = sign * q.w();
  const double s = v.norm();
  if (s < 1e-12) return 2.0 * v;
  // angle / s = 2 atan(x) / (x w), x = s / w. The corotational needle's element rotations
  // are small: below kSeriesRatio atan(x) / x by its Taylor series, whose first omitted term
  // (x^12 / 13 < 2e-17) is below double rounding, at a fraction of atan2's cost.
  constexpr double kSeriesRatio = 0.05;
  if (s < kSeriesRatio * w) {
    const double x = s / w, x2 = x * x;
    const double atan_over_x =
        1.0 - x2 * (1.0 / 3.0 - x2 * (1.0 / 5.0 - x2 * (1.0 / 7.0 - x2 * (1.0 / 9.0 - x2 / 11.0))));
    return (2.0 * atan_over_x / w) * v;
  }
  return (2.0 * std::atan2(s, w) / s) * v;
}

}  // namespace nav
