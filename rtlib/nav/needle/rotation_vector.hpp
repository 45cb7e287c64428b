#pragma once
// Rotation vectors (axis times angle, radians) to and from unit quaternions: the exponential
// and logarithm maps that the corotational needle uses for its node frames.
#include <Eigen/Core>
#include <Eigen/Geometry>

namespace nav {

/// exp: the unit quaternion of the rotation vector `theta_rad`.
Eigen::Quaterniond quaternion_from_rotation_vector(const Eigen::Vector3d& theta_rad) noexcept;

/// log: the rotation vector of unit quaternion `q`, with angle in [0, pi].
Eigen::Vector3d rotation_vector_from_quaternion(const Eigen::Quaterniond& q) noexcept;

}  // namespace nav
