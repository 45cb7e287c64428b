#include "nav/ultrasound/plus_transform.hpp"

#include <Eigen/SVD>

namespace nav::ultrasound {

Eigen::Isometry3d rigid_transform_m(const Matrix4Mm& matrix_mm) {
  Eigen::Matrix3d rotation;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) rotation(r, c) = matrix_mm[static_cast<std::size_t>(4 * r + c)];
  }
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(rotation, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Isometry3d transform = Eigen::Isometry3d::Identity();
  transform.linear() = svd.matrixU() * svd.matrixV().transpose();
  transform.translation() = 1e-3 * Eigen::Vector3d(matrix_mm[3], matrix_mm[7], matrix_mm[11]);
  return transform;
}

}  // namespace nav::ultrasound
