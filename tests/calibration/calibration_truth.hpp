#pragma once
// Synthetic truth for the calibration tests: seeded random rotations and noise.
#include <cmath>
#include <random>
#include <string>

#include "nav/calibration/rigid_transform.hpp"

namespace nav::calibration::testing {

/// The station's URDF in the source tree.
inline const std::string kStationUrdf = std::string(NAV_TEST_DATA_DIR) + "/../../calibration/urdf/station.urdf";

/// A rotation by a uniformly drawn axis and an angle uniform in [0, max_angle_rad].
inline Eigen::Matrix3d random_rotation(std::mt19937_64& rng, double max_angle_rad) {
  std::normal_distribution<double> normal(0.0, 1.0);
  std::uniform_real_distribution<double> angle(0.0, max_angle_rad);
  const Eigen::Vector3d axis(normal(rng), normal(rng), normal(rng));
  return Eigen::AngleAxisd(angle(rng), axis.normalized()).toRotationMatrix();
}

/// A vector of independent N(0, sigma^2) components.
inline Eigen::Vector3d gaussian_vector(std::mt19937_64& rng, double sigma) {
  std::normal_distribution<double> normal(0.0, sigma);
  return {normal(rng), normal(rng), normal(rng)};
}

/// A transform from a rotation and a translation.
inline Transform transform(const Eigen::Matrix3d& rotation, const Eigen::Vector3d& t_m) {
  Transform result = Transform::Identity();
  result.linear() = rotation;
  result.translation() = t_m;
  return result;
}

}  // namespace nav::calibration::testing
