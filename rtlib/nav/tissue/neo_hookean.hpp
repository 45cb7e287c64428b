#pragma once
// The compressible neo-Hookean law W = mu/2 (tr F^T F - 3) - mu ln J + lambda/2 (ln J)^2 of the
// accuracy reference: stress, its directional derivative and energy density. Internal to the
// tissue models' .cpp files.
#include <Eigen/Dense>
#include <cmath>

#include "nav/tissue/elastic_material.hpp"

namespace nav {

/// What the stress and its derivative at one F share: F^-T and ln J. Expects det F > 0.
struct NeoHookeanKinematics {
  Eigen::Matrix3d f_inverse_t;
  double log_j = 0.0;
  explicit NeoHookeanKinematics(const Eigen::Matrix3d& f)
      : f_inverse_t(f.inverse().transpose()), log_j(std::log(f.determinant())) {}
};

/// First Piola-Kirchhoff stress mu (F - F^-T) + lambda ln J F^-T, in Pa.
inline Eigen::Matrix3d neo_hookean_stress(const Eigen::Matrix3d& f, const NeoHookeanKinematics& k,
                                          const LameParameters& lame) {
  return lame.mu_pa * (f - k.f_inverse_t) + (lame.lambda_pa * k.log_j) * k.f_inverse_t;
}

/// Derivative of neo_hookean_stress at F along dF:
/// mu dF + (mu - lambda ln J) F^-T dF^T F^-T + lambda tr(F^-1 dF) F^-T.
inline Eigen::Matrix3d neo_hookean_stress_derivative(const NeoHookeanKinematics& k, const Eigen::Matrix3d& df,
                                                     const LameParameters& lame) {
  return lame.mu_pa * df + (lame.mu_pa - lame.lambda_pa * k.log_j) * (k.f_inverse_t * df.transpose() * k.f_inverse_t) +
         (lame.lambda_pa * (k.f_inverse_t.transpose() * df).trace()) * k.f_inverse_t;
}

/// Energy density in J/m^3; +infinity for det F <= 0.
inline double neo_hookean_energy_density(const Eigen::Matrix3d& f, const LameParameters& lame) {
  const double j = f.determinant();
  if (!(j > 0.0)) return HUGE_VAL;
  const double log_j = std::log(j);
  return 0.5 * lame.mu_pa * (f.squaredNorm() - 3.0) - lame.mu_pa * log_j + 0.5 * lame.lambda_pa * log_j * log_j;
}

}  // namespace nav
