#pragma once
// Rigid poses of tracked tools: a position in metres and a unit quaternion, with the few
// operations fusion needs (composition, inverse, and motion along the geodesic between two
// poses, which interpolates or, past its end, extrapolates at constant velocity).
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "nav/core/clock.hpp"
#include "nav/needle/rotation_vector.hpp"

namespace nav {

/// A rigid transform named to_from_from (tracker_from_tool maps tool points into the tracker): x_to = rotation * x_from
/// + position_m.
struct RigidPose {
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();
};

/// A pose measured at a time on the monotonic clock.
struct TimedPose {
  TimeNs time_ns = 0;
  RigidPose pose;
};

/// a_from_c = a_from_b * b_from_c.
inline RigidPose compose(const RigidPose& a_from_b, const RigidPose& b_from_c) noexcept {
  return {a_from_b.rotation * b_from_c.position_m + a_from_b.position_m, a_from_b.rotation * b_from_c.rotation};
}

/// b_from_a from a_from_b.
inline RigidPose inverse(const RigidPose& a_from_b) noexcept {
  const Eigen::Quaterniond r = a_from_b.rotation.conjugate();
  return {-(r * a_from_b.position_m), r};
}

/// The rotation from `a` to `b` as a rotation vector in a's body frame (radians).
inline Eigen::Vector3d relative_rotation_vector(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) noexcept {
  return rotation_vector_from_quaternion(a.conjugate() * b);
}

/// The pose at `fraction` along the constant-velocity path from `a` (0) to `b` (1): linear in
/// position, SLERP in rotation (the shorter way). Fractions above 1 extrapolate the same
/// linear and angular velocity, which is exact for constant-rate motion.
inline RigidPose geodesic(const RigidPose& a, const RigidPose& b, double fraction) noexcept {
  const Eigen::Vector3d step_m = b.position_m - a.position_m;
  const Eigen::Vector3d turn_rad = relative_rotation_vector(a.rotation, b.rotation);
  return {a.position_m + fraction * step_m, a.rotation * quaternion_from_rotation_vector(fraction * turn_rad)};
}

}  // namespace nav
