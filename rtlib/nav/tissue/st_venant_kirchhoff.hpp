#pragma once
// The St Venant-Kirchhoff law with Picinbono's per-tetrahedron incompressibility penalty, in
// the gradient form used by the tetrahedral FEM kernels. Picinbono's non-linear tensor-mass
// (digest 001, eqs. 13-15) is the same element energy V0 W(F) expanded in the nodal
// displacements, with alpha_j = +grad Lambda_j and the factor V(T) folded in (the two typos of
// the printed equations); evaluating it through F = sum x_a g_a^T costs a fraction of the 280
// stored coefficients per tetrahedron. Internal to the tissue models' .cpp files.
#include <Eigen/Dense>
#include <Eigen/Eigenvalues>
#include <cmath>

#include "nav/tissue/elastic_material.hpp"

namespace nav {

/// Green-Lagrange strain E = (F^T F - I) / 2.
inline Eigen::Matrix3d green_strain(const Eigen::Matrix3d& f) {
  Eigen::Matrix3d e = 0.5 * (f.transpose() * f);
  e.diagonal().array() -= 0.5;
  return e;
}

/// The cofactor matrix det(F) F^-T = d det(F) / dF.
inline Eigen::Matrix3d cofactor(const Eigen::Matrix3d& f) {
  Eigen::Matrix3d c;
  c.col(0) = f.col(1).cross(f.col(2));
  c.col(1) = f.col(2).cross(f.col(0));
  c.col(2) = f.col(0).cross(f.col(1));
  return c;
}

/// Hooke's law lambda tr(e) I + 2 mu e of the symmetric part of a strain e, in Pa: the small
/// strain law, and the St Venant-Kirchhoff law of the Green-Lagrange strain.
inline Eigen::Matrix3d hooke_stress(const Eigen::Matrix3d& strain, const LameParameters& lame) {
  Eigen::Matrix3d s = lame.mu_pa * (strain + strain.transpose());
  s.diagonal().array() += lame.lambda_pa * strain.trace();
  return s;
}

/// Second Piola-Kirchhoff stress S = lambda tr(E) I + 2 mu E of the St Venant-Kirchhoff law
/// (without the penalty), in Pa.
inline Eigen::Matrix3d stvk_second_piola(const Eigen::Matrix3d& f, const LameParameters& lame) {
  return hooke_stress(green_strain(f), lame);
}

/// First Piola-Kirchhoff stress of W = lambda/2 tr(E)^2 + mu E:E + gain |J - 1|^3 / 3, in Pa.
/// The penalty's force on vertex p, -V0 gain sign(dV) (dV/V0)^2 grad_p V, is Picinbono's
/// incompressibility force with N_p = grad_p V (area-weighted, so that it derives from a
/// potential and restores the rest volume in both directions).
inline Eigen::Matrix3d stvk_stress(const Eigen::Matrix3d& f, const LameParameters& lame, double gain_pa) {
  const double dilation = f.determinant() - 1.0;
  return f * stvk_second_piola(f, lame) + (gain_pa * std::abs(dilation) * dilation) * cofactor(f);
}

/// The symmetric matrix s with its negative eigenvalues replaced by zero. A positive definite
/// s (every leading minor positive) is returned as is; the worst case, every element under
/// compression, costs one closed-form 3x3 eigen-decomposition per element.
inline Eigen::Matrix3d positive_part(const Eigen::Matrix3d& s) {
  if (s(0, 0) > 0.0 && s(0, 0) * s(1, 1) - s(0, 1) * s(1, 0) > 0.0 && s.determinant() > 0.0) return s;
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen;
  eigen.computeDirect(s);
  return eigen.eigenvectors() * eigen.eigenvalues().cwiseMax(0.0).asDiagonal() * eigen.eigenvectors().transpose();
}

/// The stress the implicit tangent is taken with: positive_part(stvk_second_piola(F)).
inline Eigen::Matrix3d stvk_tangent_stress(const Eigen::Matrix3d& f, const LameParameters& lame) {
  return positive_part(stvk_second_piola(f, lame));
}

/// Directional derivative of stvk_stress at F along dF, made positive semi-definite for the
/// implicit solvers: dF S+ + F dS with dS the material derivative and S+ = `tangent_stress`
/// (stvk_tangent_stress(F)), plus the penalty's 2 gain |J - 1| (cof F : dF) cof F. Each term
/// has a non-negative work dF : term: the material one C dE : dE, the geometric one
/// tr(dF S+ dF^T), the penalty's a square. Under compression S has negative eigenvalues and
/// the exact geometric term would make the tangent indefinite (CG then stops early); under
/// tension S+ = S and the tangent is exact but for the penalty's term in d(cof F), of order
/// (J - 1)^2, left out so that the tangent stays symmetric.
inline Eigen::Matrix3d stvk_stress_derivative(const Eigen::Matrix3d& f, const Eigen::Matrix3d& df,
                                              const Eigen::Matrix3d& tangent_stress, const LameParameters& lame,
                                              double gain_pa) {
  const Eigen::Matrix3d ds = hooke_stress(f.transpose() * df, lame);  // of dE, the symmetric part of F^T dF
  const Eigen::Matrix3d c = cofactor(f);
  const double penalty = 2.0 * gain_pa * std::abs(f.determinant() - 1.0) * (c.array() * df.array()).sum();
  return df * tangent_stress + f * ds + penalty * c;
}

/// Energy density of stvk_stress, in J/m^3.
inline double stvk_energy_density(const Eigen::Matrix3d& f, const LameParameters& lame, double gain_pa) {
  const Eigen::Matrix3d e = green_strain(f);
  const double trace = e.trace();
  const double dilation = std::abs(f.determinant() - 1.0);
  return 0.5 * lame.lambda_pa * trace * trace + lame.mu_pa * e.squaredNorm() +
         gain_pa * dilation * dilation * dilation / 3.0;
}

}  // namespace nav
