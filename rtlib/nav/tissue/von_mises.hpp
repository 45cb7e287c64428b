#pragma once
// The von Mises equivalent stress of a symmetric stress, shared by the static solvers.
#include <cmath>

namespace nav {

/// sqrt(((s11 - s22)^2 + (s22 - s33)^2 + (s33 - s11)^2) / 2 + 3 (s12^2 + s23^2 + s13^2)) of the
/// six stresses xx, yy, zz and the three shears (in any order), in Pa.
inline double von_mises_pa(const double* s) {
  const double normal = (s[0] - s[1]) * (s[0] - s[1]) + (s[1] - s[2]) * (s[1] - s[2]) + (s[2] - s[0]) * (s[2] - s[0]);
  return std::sqrt(0.5 * normal + 3.0 * (s[3] * s[3] + s[4] * s[4] + s[5] * s[5]));
}

}  // namespace nav
