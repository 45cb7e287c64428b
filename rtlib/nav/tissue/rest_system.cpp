#include "nav/tissue/rest_system.hpp"

#include <Eigen/Sparse>
#include <algorithm>
#include <cmath>
#include <vector>

#include "nav/tissue/tet_fem_kernels.hpp"
#include "nav/tissue/tet_kernels.hpp"
#include "nav/tissue/tissue_loads.hpp"

namespace nav::detail {
namespace {

void set_coefficients(TetFemTables& tables) {
  const TissueSolverOptions& o = tables.options;
  const double h = o.step_s;
  if (o.integrator == Integrator::quasi_static) {  // Rayleigh damping against du / h, no inertia
    tables.mass_coefficient = o.rayleigh_mass_per_s / h;
    tables.stiffness_coefficient = 1.0 + o.rayleigh_stiffness_s / h;
    tables.spring_coefficient = 1.0;
  } else {
    tables.mass_coefficient = 1.0 + h * o.rayleigh_mass_per_s;
    tables.stiffness_coefficient = h * h + h * o.rayleigh_stiffness_s;
    tables.spring_coefficient = h * h;
  }
}

/// The rest system's lower-triangle entries over free dofs, and its 3x3 node blocks.
Eigen::SparseMatrix<double> assemble(TetFemTables& tables) {
  const auto free_dofs = static_cast<Eigen::Index>(3 * tables.free_nodes.size());
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(tables.tets.size() * 78 + static_cast<std::size_t>(free_dofs));
  std::vector<double> blocks(9 * static_cast<std::size_t>(tables.node_count), 0.0);
  auto add = [&](std::int32_t node_a, int i, std::int32_t node_b, int j, double value) {
    if (node_a == node_b) blocks[9 * static_cast<std::size_t>(node_a) + 3 * j + i] += value;
    const std::int32_t fa = tables.free_index[static_cast<std::size_t>(node_a)];
    const std::int32_t fb = tables.free_index[static_cast<std::size_t>(node_b)];
    if (fa < 0 || fb < 0) return;
    const Eigen::Index row = 3 * fa + i, col = 3 * fb + j;
    if (row >= col) triplets.emplace_back(row, col, value);
  };
  for (std::size_t e = 0; e < tables.tets.size(); ++e) {
    Matrix43 gradients;
    for (int a = 0; a < 4; ++a)
      for (int c = 0; c < 3; ++c) gradients(a, c) = tables.gradients[12 * e + 3 * a + c];
    const Matrix12 ke = element_stiffness(gradients, tables.lame[e], tables.volume_m3[e]);
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < 4; ++b)
        for (int i = 0; i < 3; ++i)
          for (int j = 0; j < 3; ++j)
            add(tables.tets[e][a], i, tables.tets[e][b], j, tables.stiffness_coefficient * ke(3 * a + i, 3 * b + j));
  }
  for (std::int64_t node = 0; node < tables.node_count; ++node) {
    double diagonal = tables.mass_coefficient * tables.mass_kg[static_cast<std::size_t>(node)];
    for (int i = 0; i < 3; ++i) add(static_cast<std::int32_t>(node), i, static_cast<std::int32_t>(node), i, diagonal);
  }
  for (std::int32_t node : tables.spring_nodes)
    for (int i = 0; i < 3; ++i) add(node, i, node, i, tables.spring_coefficient * tables.spring_stiffness_n_m);

  tables.block_inverse.resize(blocks.size());
  tables.diagonal_inverse.resize(3 * static_cast<std::size_t>(tables.node_count));
  for (std::int64_t node = 0; node < tables.node_count; ++node) {
    const Eigen::Map<const Eigen::Matrix3d> block(blocks.data() + 9 * node);
    const bool usable = tables.free_index[static_cast<std::size_t>(node)] >= 0 && block.determinant() > 0.0;
    Eigen::Map<Eigen::Matrix3d>(tables.block_inverse.data() + 9 * node) =
        usable ? Eigen::Matrix3d(block.inverse()) : Eigen::Matrix3d::Zero();
    for (int i = 0; i < 3; ++i) tables.diagonal_inverse[3 * node + i] = usable ? 1.0 / block(i, i) : 0.0;
  }
  Eigen::SparseMatrix<double> matrix(free_dofs, free_dofs);
  matrix.setFromTriplets(triplets.begin(), triplets.end());
  return matrix;
}

/// 2 / sqrt(largest eigenvalue of M^-1 (K + Ks)) over free dofs, by a fixed count of power
/// iterations on M^-1/2 (K + Ks) M^-1/2 from a deterministic start.
double stable_step_estimate(const TetFemTables& tables) {
  constexpr int kPowerIterations = 100;
  const auto n3 = static_cast<std::size_t>(3 * tables.node_count);
  std::vector<double> identity_rotations(9 * tables.tets.size(), 0.0);
  for (std::size_t e = 0; e < tables.tets.size(); ++e)
    for (int d = 0; d < 3; ++d) identity_rotations[9 * e + 4 * d] = 1.0;
  const std::vector<double> rest_stresses(9 * tables.tets.size(), 0.0);  // S = 0 at rest
  std::vector<double> x(n3), scaled(n3), product(n3);
  for (std::size_t i = 0; i < n3; ++i)
    x[i] = (i % 7 == 0 ? 1.0 : 0.0) + 1e-3 * static_cast<double>(i % 13) - (i % 2 ? 0.5 : 0.0);
  double eigenvalue = 0.0;
  for (int iteration = 0; iteration < kPowerIterations; ++iteration) {
    zero_constrained(tables, x);
    double norm_squared = 0.0;
    for (double value : x) norm_squared += value * value;
    if (!(norm_squared > 0.0)) return 0.0;
    const double inverse_norm = 1.0 / std::sqrt(norm_squared);
    for (std::size_t i = 0; i < n3; ++i) {
      x[i] *= inverse_norm;
      scaled[i] = tables.mass_kg[i / 3] > 0.0 ? x[i] / std::sqrt(tables.mass_kg[i / 3]) : 0.0;
    }
    std::fill(product.begin(), product.end(), 0.0);
    add_stiffness_product(tables, tables.rest_m, identity_rotations, rest_stresses, scaled, 1.0, product);
    add_spring_product(tables, scaled, 1.0, product);
    eigenvalue = 0.0;
    for (std::size_t i = 0; i < n3; ++i) {
      x[i] = tables.mass_kg[i / 3] > 0.0 ? product[i] / std::sqrt(tables.mass_kg[i / 3]) : 0.0;
    }
    zero_constrained(tables, x);
    for (std::size_t i = 0; i < n3; ++i) eigenvalue += x[i] * x[i];
    eigenvalue = std::sqrt(eigenvalue);  // |B x| for unit x: converges to the largest eigenvalue
  }
  return eigenvalue > 0.0 ? 2.0 / std::sqrt(eigenvalue) : 0.0;
}

/// The element volume change |J - 1| up to which the explicit step is kept stable under
/// Picinbono's penalty (ten times what the penalty is there to allow, Table 2: 0.2 to 1 %).
constexpr double kPenaltyDesignDilation = 0.1;

/// The factor on the rest system's stable step that keeps it stable under the
/// incompressibility penalty: the penalty's tangent 2 gain |J - 1| (cof F : dF) cof F adds
/// 2 gain |J - 1| to the P-wave modulus lambda + 2 mu, and the step limit goes as one over the
/// P-wave speed. The worst element decides.
double penalty_step_factor(const TetFemTables& tables) {
  const double gain_pa =
      tables.options.law == ElementLaw::st_venant_kirchhoff ? tables.options.incompressibility_gain_pa : 0.0;
  double factor = 1.0;
  for (const LameParameters& lame : tables.lame) {
    const double p_wave_pa = lame.lambda_pa + 2.0 * lame.mu_pa;
    factor = std::min(factor, std::sqrt(p_wave_pa / (p_wave_pa + 2.0 * gain_pa * kPenaltyDesignDilation)));
  }
  return factor;
}

}  // namespace

Status build_rest_system(TetFemTables& tables) {
  set_coefficients(tables);
  const bool quasi_static = tables.options.integrator == Integrator::quasi_static;
  if (quasi_static && tables.fixed_nodes.empty() && tables.prescribed_nodes.empty() && tables.spring_nodes.empty())
    return Error{
        .message = "a quasi-static model needs fixed nodes, springs or a prescribed region to remove rigid motions",
        .field = "fixed_nodes"};
  const Eigen::SparseMatrix<double> matrix = assemble(tables);
  const bool needs_factor = tables.options.integrator != Integrator::explicit_central_difference &&
                            tables.options.solver == LinearSolver::ldlt_warped;
  if (needs_factor)
    if (auto s = tables.factor.factor(matrix, quasi_static ? "fixed_nodes" : "step_s"); !s) return s;
  tables.stable_step_s = stable_step_estimate(tables) * penalty_step_factor(tables);
  return Done{};
}

}  // namespace nav::detail
