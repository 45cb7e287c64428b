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
  return (2.0 * std::atan2(s, w) / s) * v;
}

}  // namespace nav
