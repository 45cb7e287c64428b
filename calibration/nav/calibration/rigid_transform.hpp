#pragma once
// Rigid transforms for the calibration library: a_from_b maps points of frame b into frame a.
// Eigen's Isometry3d, plus the few conversions (URDF rpy, interpolation) calibrations share.
#include <Eigen/Geometry>

namespace nav::calibration {

/// A rigid transform a_from_b (rotation and translation in metres).
using Transform = Eigen::Isometry3d;

/// The transform with rotation `q` (normalised here) and translation `t_m`.
Transform make_transform(const Eigen::Quaterniond& q, const Eigen::Vector3d& t_m);

/// URDF fixed-axis roll, pitch, yaw (R = Rz(yaw) Ry(pitch) Rx(roll)) of a rotation, radians.
Eigen::Vector3d rotation_to_rpy(const Eigen::Matrix3d& rotation);
/// The rotation of URDF roll, pitch, yaw angles in radians.
Eigen::Matrix3d rpy_to_rotation(const Eigen::Vector3d& rpy);

/// The pose a fraction `alpha` (0..1) of the way from `a` to `b`: linear in translation,
/// SLERP in rotation.
Transform interpolate(const Transform& a, const Transform& b, double alpha);

/// The angle in radians of the rotation taking `a` to `b`.
double rotation_angle_rad(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b);

}  // namespace nav::calibration
