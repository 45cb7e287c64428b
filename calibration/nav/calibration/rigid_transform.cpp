#include "nav/calibration/rigid_transform.hpp"

#include <algorithm>
#include <cmath>

namespace nav::calibration {

Transform make_transform(const Eigen::Quaterniond& q, const Eigen::Vector3d& t_m) {
  Transform transform = Transform::Identity();
  transform.linear() = q.normalized().toRotationMatrix();
  transform.translation() = t_m;
  return transform;
}

Eigen::Vector3d rotation_to_rpy(const Eigen::Matrix3d& r) {
  const double pitch = std::asin(std::clamp(-r(2, 0), -1.0, 1.0));
  if (std::abs(r(2, 0)) > 1.0 - 1e-12) {  // gimbal lock: put everything in yaw
    return {0.0, pitch, std::atan2(-r(0, 1), r(1, 1))};
  }
  return {std::atan2(r(2, 1), r(2, 2)), pitch, std::atan2(r(1, 0), r(0, 0))};
}

Eigen::Matrix3d rpy_to_rotation(const Eigen::Vector3d& rpy) {
  return (Eigen::AngleAxisd(rpy.z(), Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(rpy.y(), Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(rpy.x(), Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

Transform interpolate(const Transform& a, const Transform& b, double alpha) {
  const Eigen::Quaterniond qa(a.rotation());
  const Eigen::Quaterniond qb(b.rotation());
  const Eigen::Vector3d t_m = (1.0 - alpha) * a.translation() + alpha * b.translation();
  return make_transform(qa.slerp(alpha, qb), t_m);
}

double rotation_angle_rad(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  return Eigen::AngleAxisd(a.transpose() * b).angle();
}

}  // namespace nav::calibration
