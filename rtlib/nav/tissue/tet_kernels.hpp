#pragma once
// Element kernels of the linear tetrahedron shared by the tissue models: shape-function
// gradients, the strain-displacement and elasticity matrices, the linear stress of a
// displacement gradient and the rotation of a deformation gradient. Internal to the tissue
// models' .cpp files (it brings in Eigen).
#include <Eigen/Dense>
#include <array>
#include <cstddef>

#include "nav/mesh/tet_mesh.hpp"
#include "nav/tissue/elastic_material.hpp"
#include "nav/tissue/polar_iterations.hpp"

namespace nav {

using Matrix43 = Eigen::Matrix<double, 4, 3>;
using Matrix6x12 = Eigen::Matrix<double, 6, 12>;
using Matrix6 = Eigen::Matrix<double, 6, 6>;
using Matrix12 = Eigen::Matrix<double, 12, 12>;

/// Row a holds the gradient of the barycentric coordinate of vertex a (constant over the
/// element), so that sum_a x_a g_a^T is the deformation gradient and sum_a g_a = 0.
Matrix43 shape_gradients(const std::array<Point3, 4>& corners_m);

/// Strain-displacement matrix B (Voigt order xx, yy, zz, xy, yz, zx, engineering shears).
Matrix6x12 strain_displacement(const Matrix43& gradients);

/// Isotropic elasticity matrix D in the same Voigt order.
Matrix6 elasticity_matrix(const LameParameters& lame);

/// Stiffness V B^T D B of an element of volume `volume_m3`.
Matrix12 element_stiffness(const Matrix43& gradients, const LameParameters& lame, double volume_m3);

/// Cauchy stress of the small strain sym(h) of displacement gradient h:
/// lambda tr(eps) I + 2 mu eps.
inline Eigen::Matrix3d linear_stress(const Eigen::Matrix3d& h, const LameParameters& lame) {
  const Eigen::Matrix3d strain = 0.5 * (h + h.transpose());
  Eigen::Matrix3d stress = (2.0 * lame.mu_pa) * strain;
  stress.diagonal().array() += lame.lambda_pa * strain.trace();
  return stress;
}

/// Strain energy density mu eps:eps + lambda/2 tr(eps)^2 of displacement gradient h, in J/m^3.
inline double linear_energy_density(const Eigen::Matrix3d& h, const LameParameters& lame) {
  const Eigen::Matrix3d strain = 0.5 * (h + h.transpose());
  const double trace = strain.trace();
  return lame.mu_pa * strain.squaredNorm() + 0.5 * lame.lambda_pa * trace * trace;
}

/// Matrices decomposed together by polar_rotations, so that the iterations of independent
/// elements interleave (and vectorise) instead of waiting on each other's divisions.
inline constexpr int kPolarLanes = 8;

/// kPolarLanes 3x3 matrices, structure of arrays: entry (i, j) of lane l at [3 j + i][l].
using PolarBatch = std::array<std::array<double, kPolarLanes>, 9>;

/// Replaces every lane by the orthogonal factor of its polar decomposition f = R S, by scaled
/// Newton iterations R <- (g R + R^-T / g) / 2 with Frobenius scaling g, each lane until it
/// converged (kPolarConvergedChange) or kPolarIterations. Expects det > 0 in every lane (fill
/// unused lanes with the identity). At most kPolarIterations whatever the matrices; each lane's
/// result does not depend on the other lanes.
void polar_rotations(PolarBatch& batch) noexcept;

/// The polar rotation of one matrix (lane 0 of a batch): for init-time and diagnostic code.
Eigen::Matrix3d polar_rotation(const Eigen::Matrix3d& f);

/// Calls load(index, f) for every index in [0, count) in order, to get the matrix to
/// decompose (returning false to skip it: its lane holds the identity), decomposes them
/// kPolarLanes at a time and calls store(index, rotation) for every index not skipped, in
/// order. No allocation.
template <class Load, class Store>
void for_each_polar_rotation(std::size_t count, Load&& load, Store&& store) noexcept {
  PolarBatch batch;
  std::array<bool, kPolarLanes> used{};
  for (std::size_t first = 0; first < count; first += kPolarLanes) {
    for (int l = 0; l < kPolarLanes; ++l) {
      Eigen::Matrix3d f = Eigen::Matrix3d::Identity();
      const std::size_t index = first + static_cast<std::size_t>(l);
      used[l] = index < count && load(index, f);
      if (!used[l]) f.setIdentity();
      for (int k = 0; k < 9; ++k) batch[k][l] = f(k % 3, k / 3);
    }
    polar_rotations(batch);
    for (int l = 0; l < kPolarLanes; ++l) {
      if (!used[l]) continue;
      Eigen::Matrix3d rotation;
      for (int k = 0; k < 9; ++k) rotation(k % 3, k / 3) = batch[k][l];
      store(first + static_cast<std::size_t>(l), rotation);
    }
  }
}

}  // namespace nav
