#pragma once
// The compressible neo-Hookean law W = mu/2 (tr F^T F - 3) - mu ln J + lambda/2 (ln J)^2 of the
// accuracy reference: stress, its directional derivative and energy density. Internal to the
// tissue models' .cpp files.
#include <Eigen/Dense>
#include <cmath>

#include "nav/tissue/elastic_material.hpp"

namespace nav {

/// First Piola-Kirchhoff stress mu (F - F^-T) + lambda ln J F^-T, in Pa. Expects det F > 0.
inline Eigen::Matrix3d neo_hookean_stress(const Eigen::Matrix3d& f, const LameParameters& lame) {
  const Eigen::Matrix3d f_inverse_t = f.inverse().transpose();
  return lame.mu_pa * (f - f_inverse_t) + (lame.lambda_pa * std::log(f.determinant())) * f_inverse_t;
}

/// Derivative of neo_hookean_stress at F along dF:
/// mu dF + (mu - lambda ln J) F^-T dF^T F^-T + lambda tr(F^-1 dF) F^-T.
inline Eigen::Matrix3d neo_hookean_stress_derivative(const Eigen::Matrix3d& f, const Eigen::Matrix3d& df,
                                                     const LameParameters& lame) {
  const Eigen::Matrix3d f_inverse = f.inverse();
  const Eigen::Matrix3d f_inverse_t = f_inverse.transpose();
  const double log_j = std::log(f.determinant());
  return lame.mu_pa * df + (lame.mu_pa - lame.lambda_pa * log_j) * (f_inverse_t * df.transpose() * f_inverse_t) +
         (lame.lambda_pa * (f_inverse * df).trace()) * f_inverse_t;
}

/// Energy density in J/m^3; +infinity for det F <= 0.
inline double neo_hookean_energy_density(const Eigen::Matrix3d& f, const LameParameters& lame) {
  const double j = f.determinant();
  if (!(j > 0.0)) return HUGE_VAL;
  const double log_j = std::log(j);
  return 0.5 * lame.mu_pa * (f.squaredNorm() - 3.0) - lame.mu_pa * log_j + 0.5 * lame.lambda_pa * log_j * log_j;
}

}  // namespace nav
