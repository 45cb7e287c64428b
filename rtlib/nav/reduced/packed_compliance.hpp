#pragma once
// A symmetric 3x3 compliance kept as 6 values (xx, xy, xz, yy, yz, zz): the layout of the
// missing compliances per node (ReducedErrorCalibration, NeedleTissueModel).
#include <Eigen/Core>

namespace nav {

/// Writes the upper triangle of `c` into out[0..5].
inline void pack_compliance(const Eigen::Matrix3d& c, double* out) noexcept {
  out[0] = c(0, 0), out[1] = c(0, 1), out[2] = c(0, 2), out[3] = c(1, 1), out[4] = c(1, 2), out[5] = c(2, 2);
}

/// The symmetric matrix of packed[0..5].
inline Eigen::Matrix3d unpack_compliance(const double* packed) noexcept {
  const double* m = packed;
  return (Eigen::Matrix3d() << m[0], m[1], m[2], m[1], m[3], m[4], m[2], m[4], m[5]).finished();
}

}  // namespace nav
