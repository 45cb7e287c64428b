#include "nav/tissue/linear_solve.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "nav/tissue/tet_fem_kernels.hpp"
#include "nav/tissue/tet_fem_tables.hpp"
#include "nav/tissue/tissue_loads.hpp"

namespace nav::detail {
namespace {

using ConstMatrix3 = Eigen::Map<const Eigen::Matrix3d>;
using ConstVector3 = Eigen::Map<const Eigen::Vector3d>;

double dot(std::span<const double> a, std::span<const double> b) {
  double sum = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) sum += a[i] * b[i];
  return sum;
}

/// out = A p on free nodes, zero on constrained ones.
void apply_system(const TetFemTables& tables, const TetFemData& data, std::span<const double> p,
                  std::span<double> out) {
  for (std::size_t i = 0; i < out.size(); ++i) out[i] = tables.mass_coefficient * tables.mass_kg[i / 3] * p[i];
  add_stiffness_product(tables, data.positions_m, data.element_rotations, data.tangent_stresses, p,
                        tables.stiffness_coefficient, out);
  add_spring_product(tables, p, tables.spring_coefficient, out);
  zero_constrained(tables, out);
}

/// out = R A0^-1 R^T r over free nodes: the rest factor warped by the node rotations.
void apply_warped_ldlt(const TetFemTables& tables, TetFemData& data, std::span<const double> r, std::span<double> out) {
  const std::size_t free3 = 3 * tables.free_nodes.size();
  const std::span<double> local = data.free_work.first(free3), work = data.free_work.subspan(free3, free3);
  for (std::size_t k = 0; k < tables.free_nodes.size(); ++k) {
    const auto node = static_cast<std::size_t>(tables.free_nodes[k]);
    Eigen::Map<Eigen::Vector3d>(local.data() + 3 * k) =
        ConstMatrix3(data.node_rotations.data() + 9 * node).transpose() * ConstVector3(r.data() + 3 * node);
  }
  tables.factor.solve_in_place(local, work);
  std::fill(out.begin(), out.end(), 0.0);
  for (std::size_t k = 0; k < tables.free_nodes.size(); ++k) {
    const auto node = static_cast<std::size_t>(tables.free_nodes[k]);
    Eigen::Map<Eigen::Vector3d>(out.data() + 3 * node) =
        ConstMatrix3(data.node_rotations.data() + 9 * node) * ConstVector3(local.data() + 3 * k);
  }
}

/// out = P^-1 r: the rest diagonal, the rest 3x3 blocks or the rest factor, the last two
/// warped by the node rotations.
void precondition(const TetFemTables& tables, TetFemData& data, std::span<const double> r, std::span<double> out) {
  const std::span<const double> node_rotations = data.node_rotations;
  if (tables.options.solver == LinearSolver::ldlt_warped) {
    apply_warped_ldlt(tables, data, r, out);
    return;
  }
  if (tables.options.solver == LinearSolver::cg_jacobi) {
    for (std::size_t i = 0; i < out.size(); ++i) out[i] = tables.diagonal_inverse[i] * r[i];
    return;
  }
  for (std::int64_t node = 0; node < tables.node_count; ++node) {
    const ConstMatrix3 rotation(node_rotations.data() + 9 * node);
    const ConstMatrix3 inverse(tables.block_inverse.data() + 9 * node);
    Eigen::Map<Eigen::Vector3d>(out.data() + 3 * node) =
        rotation * (inverse * (rotation.transpose() * ConstVector3(r.data() + 3 * node)));
  }
}

/// A relative residual at which the solve is exact to rounding: iterating further only
/// stirs rounding noise.
constexpr double kExactResidual = 1e-14;

void solve_by_cg(const TetFemTables& tables, TetFemData& data) {
  const std::span<double> x = data.solution, r = data.residual, z = data.preconditioned, p = data.direction,
                          q = data.product;
  std::fill(x.begin(), x.end(), 0.0);
  std::copy(data.rhs.begin(), data.rhs.end(), r.begin());
  const double rhs_norm = std::sqrt(dot(r, r));
  precondition(tables, data, r, z);
  std::copy(z.begin(), z.end(), p.begin());
  double rz = dot(r, z);
  int iterations = 0;
  const double converged_norm_squared = kExactResidual * kExactResidual * rhs_norm * rhs_norm;
  while (iterations < tables.options.cg_iterations && rz > 0.0 && dot(r, r) > converged_norm_squared) {
    apply_system(tables, data, p, q);
    const double curvature = dot(p, q);
    if (!(curvature > 0.0)) break;
    const double alpha = rz / curvature;
    for (std::size_t i = 0; i < x.size(); ++i) {
      x[i] += alpha * p[i];
      r[i] -= alpha * q[i];
    }
    if (++iterations == tables.options.cg_iterations) break;  // the next direction would go unused
    precondition(tables, data, r, z);
    const double rz_next = dot(r, z);
    const double beta = rz_next / rz;
    rz = rz_next;
    for (std::size_t i = 0; i < p.size(); ++i) p[i] = z[i] + beta * p[i];
  }
  data.report.solver_iterations = iterations;
  data.report.solver_relative_residual = rhs_norm > 0.0 ? std::sqrt(dot(r, r)) / rhs_norm : 0.0;
  if (data.report.solver_relative_residual > tables.options.cg_residual_bound)
    data.health.raise(HealthFlag::solver_not_converged);
}

}  // namespace

void solve_system(const TetFemTables& tables, TetFemData& data) noexcept {
  const bool warps = tables.options.solver != LinearSolver::cg_jacobi;
  if (warps && tables.options.rotation == ElementRotation::corotational)
    update_node_rotations(tables, data.element_rotations, data.node_rotations);
  solve_by_cg(tables, data);
}

}  // namespace nav::detail
