#include "nav/tissue/neo_hookean_static.hpp"

#include <Eigen/Sparse>
#include <cmath>
#include <string>

#include "nav/tissue/neo_hookean.hpp"
#include "nav/tissue/sparse_cholesky.hpp"
#include "nav/tissue/tet_fem_model.hpp"
#include "nav/tissue/tet_fem_tables.hpp"
#include "nav/tissue/tissue_loads.hpp"

namespace nav {
namespace {

using detail::TetFemTables;
using Gradients = Eigen::Map<const Eigen::Matrix<double, 4, 3, Eigen::RowMajor>>;

/// Largest line-search halvings before the increment is declared failed.
constexpr int kMaxHalvings = 40;

/// The discrete problem: element tables, which dofs are held and where they go.
struct Problem {
  const TetFemTables& tables;
  std::vector<double> rest_m;         // 3 per node
  std::vector<double> dead_load_n;    // at the full load
  std::vector<double> held_target_m;  // full imposed displacement of held dofs (0 elsewhere)
  std::vector<std::int32_t> free_of;  // dof -> free index, -1 when held
  std::int32_t free_count = 0;
};

Eigen::Matrix3d deformation_gradient(const Problem& p, std::size_t e, std::span<const double> x) {
  Eigen::Matrix<double, 3, 4> corners;
  for (int a = 0; a < 4; ++a)
    for (int i = 0; i < 3; ++i) corners(i, a) = x[3 * static_cast<std::size_t>(p.tables.tets[e][a]) + i];
  return corners * Gradients(p.tables.gradients.data() + 12 * e);
}

/// Elastic energy minus the work of the dead loads (scaled by `load`), +inf if an element inverts.
double potential_j(const Problem& p, std::span<const double> x, double load) {
  double energy_j = 0.0;
  for (std::size_t e = 0; e < p.tables.tets.size(); ++e)
    energy_j += p.tables.volume_m3[e] * neo_hookean_energy_density(deformation_gradient(p, e, x), p.tables.lame[e]);
  for (std::size_t i = 0; i < x.size(); ++i) energy_j -= load * p.dead_load_n[i] * (x[i] - p.rest_m[i]);
  return energy_j;
}

/// Out-of-balance forces (elastic restoring + dead loads) on every dof, the tangent stiffness
/// over free dofs, and tangent * step restricted to held dofs, moved to the free rows.
void linearise(const Problem& p, std::span<const double> x, double load, std::span<const double> held_step,
               std::vector<double>& residual, std::vector<Eigen::Triplet<double>>& triplets,
               std::vector<double>& held_coupling) {
  for (std::size_t i = 0; i < residual.size(); ++i) residual[i] = load * p.dead_load_n[i];
  std::fill(held_coupling.begin(), held_coupling.end(), 0.0);
  triplets.clear();
  for (std::size_t e = 0; e < p.tables.tets.size(); ++e) {
    const Gradients g(p.tables.gradients.data() + 12 * e);
    const Eigen::Matrix3d f = deformation_gradient(p, e, x);
    const double volume_m3 = p.tables.volume_m3[e];
    const Eigen::Matrix<double, 3, 4> forces = -volume_m3 * neo_hookean_stress(f, p.tables.lame[e]) * g.transpose();
    std::array<std::size_t, 12> dof{};
    for (int a = 0; a < 4; ++a)
      for (int i = 0; i < 3; ++i) {
        dof[3 * a + i] = 3 * static_cast<std::size_t>(p.tables.tets[e][a]) + i;
        residual[dof[3 * a + i]] += forces(i, a);
      }
    for (int column = 0; column < 12; ++column) {
      Eigen::Matrix3d df = Eigen::Matrix3d::Zero();
      df.row(column % 3) = g.row(column / 3);
      const Eigen::Matrix<double, 3, 4> k_column =
          volume_m3 * neo_hookean_stress_derivative(f, df, p.tables.lame[e]) * g.transpose();
      const std::int32_t free_column = p.free_of[dof[column]];
      for (int row = 0; row < 12; ++row) {
        const std::int32_t free_row = p.free_of[dof[row]];
        if (free_row < 0) continue;
        const double k = k_column(row % 3, row / 3);
        if (free_column < 0)
          held_coupling[static_cast<std::size_t>(free_row)] += k * held_step[dof[column]];
        else if (free_row >= free_column)
          triplets.emplace_back(free_row, free_column, k);
      }
    }
  }
}

/// |out-of-balance force| over free dofs at x: a descent test that, unlike the potential,
/// keeps its precision close to equilibrium.
double free_residual_norm(const Problem& p, std::span<const double> x, double load) {
  std::vector<double> residual(x.size());
  for (std::size_t i = 0; i < residual.size(); ++i) residual[i] = load * p.dead_load_n[i];
  for (std::size_t e = 0; e < p.tables.tets.size(); ++e) {
    const Eigen::Matrix<double, 3, 4> forces = -p.tables.volume_m3[e] *
                                               neo_hookean_stress(deformation_gradient(p, e, x), p.tables.lame[e]) *
                                               Gradients(p.tables.gradients.data() + 12 * e).transpose();
    for (int a = 0; a < 4; ++a)
      for (int i = 0; i < 3; ++i) residual[3 * static_cast<std::size_t>(p.tables.tets[e][a]) + i] += forces(i, a);
  }
  double sum = 0.0;
  for (std::size_t i = 0; i < residual.size(); ++i)
    if (p.free_of[i] >= 0) sum += residual[i] * residual[i];
  return std::sqrt(sum);
}

double norm(std::span<const double> v) {
  double sum = 0.0;
  for (double value : v) sum += value * value;
  return std::sqrt(sum);
}

Result<Problem> make_problem(const TetFemTables& tables, const TissueInputs& loads,
                             std::span<const DofConstraint> constraints) {
  Problem p{tables, tables.rest_m, {}, {}, {}, 0};
  const std::size_t n3 = tables.rest_m.size();
  p.dead_load_n.assign(n3, 0.0);
  TissueStepReport unused;
  detail::add_external_forces(tables, loads, tables.rest_m, p.dead_load_n, unused);
  p.held_target_m.assign(n3, 0.0);
  std::vector<bool> held(n3, false);
  for (std::int32_t node : tables.fixed_nodes)
    for (int c = 0; c < 3; ++c) held[3 * static_cast<std::size_t>(node) + c] = true;
  for (std::int32_t node : tables.prescribed_nodes)
    for (int c = 0; c < 3; ++c) {
      held[3 * static_cast<std::size_t>(node) + c] = true;
      p.held_target_m[3 * static_cast<std::size_t>(node) + c] = loads.prescribed_displacement_m[c];
    }
  for (const DofConstraint& constraint : constraints) {
    if (constraint.node < 0 || constraint.node >= tables.node_count || constraint.axis < 0 || constraint.axis > 2 ||
        !std::isfinite(constraint.displacement_m))
      return field_error("constraint on node " + std::to_string(constraint.node) + " is out of range", "constraints");
    const std::size_t i = 3 * static_cast<std::size_t>(constraint.node) + static_cast<std::size_t>(constraint.axis);
    held[i] = true;
    p.held_target_m[i] = constraint.displacement_m;
  }
  p.free_of.assign(n3, -1);
  for (std::size_t i = 0; i < n3; ++i)
    if (!held[i]) p.free_of[i] = p.free_count++;
  if (p.free_count == 0) return field_error("every degree of freedom is held", "constraints");
  return p;
}

}  // namespace

Result<NeoHookeanSolution> solve_neo_hookean_static(const TetMesh& mesh, const TissueScene& scene,
                                                    const TissueInputs& loads,
                                                    std::span<const DofConstraint> constraints,
                                                    const NeoHookeanOptions& options) {
  if (loads.probe.active)
    return field_error("the reference does not model the probe: prescribe the pressed nodes", "probe");
  if (!scene.spring_nodes.empty()) return field_error("the reference does not model frame springs", "spring_nodes");
  if (options.load_increments < 1 || options.max_newton_iterations < 1 || !(options.relative_tolerance > 0.0))
    return field_error("increments, iterations and tolerance must be positive", "options");
  TissueSolverOptions element_options;
  element_options.integrator = Integrator::explicit_central_difference;
  element_options.rotation = ElementRotation::none;
  auto model = make_tet_fem_model(mesh, scene, element_options);
  if (!model.ok()) return model.error();
  auto problem = make_problem(model.value().tables(), loads, constraints);
  if (!problem.ok()) return problem.error();
  const Problem& p = problem.value();
  const std::size_t n3 = p.rest_m.size();

  NeoHookeanSolution solution;
  solution.positions_m = p.rest_m;
  std::vector<double>& x = solution.positions_m;
  std::vector<double> residual(n3), held_coupling(static_cast<std::size_t>(p.free_count)), step(n3), trial(n3);
  std::vector<Eigen::Triplet<double>> triplets;
  Eigen::SparseMatrix<double> tangent(p.free_count, p.free_count);
  SparseCholesky factor;
  for (int increment = 1; increment <= options.load_increments; ++increment) {
    const double load = static_cast<double>(increment) / options.load_increments;
    bool converged = false;
    for (int iteration = 0; iteration < options.max_newton_iterations && !converged; ++iteration) {
      for (std::size_t i = 0; i < n3; ++i)
        step[i] = p.free_of[i] < 0 ? p.rest_m[i] + load * p.held_target_m[i] - x[i] : 0.0;
      linearise(p, x, load, step, residual, triplets, held_coupling);
      const bool held_in_place = norm(step) == 0.0;
      double free_norm = 0.0, scale = 0.0;
      for (std::size_t i = 0; i < n3; ++i) {
        scale += residual[i] * residual[i];
        if (p.free_of[i] >= 0) free_norm += residual[i] * residual[i];
      }
      solution.relative_residual = std::sqrt(free_norm / std::max(scale, 1e-300));
      if (held_in_place && solution.relative_residual <= options.relative_tolerance) {
        converged = true;
        break;
      }
      tangent.setFromTriplets(triplets.begin(), triplets.end());
      if (!factor.factor(tangent, "tangent").ok())
        return field_error("the neo-Hookean tangent could not be factored", "tangent");
      Eigen::VectorXd rhs(p.free_count);
      for (std::size_t i = 0; i < n3; ++i)
        if (p.free_of[i] >= 0) rhs[p.free_of[i]] = residual[i] - held_coupling[static_cast<std::size_t>(p.free_of[i])];
      const Eigen::VectorXd free_step = factor.solve(rhs);
      for (std::size_t i = 0; i < n3; ++i)
        if (p.free_of[i] >= 0) step[i] = free_step[p.free_of[i]];
      // Line search: no inverted element, and (once the held dofs are in place) a lower
      // potential or a smaller out-of-balance force.
      const double before_j = potential_j(p, x, load);
      const double before_n = std::sqrt(free_norm);
      double fraction = 1.0;
      int halvings = 0;
      for (; halvings < kMaxHalvings; ++halvings, fraction *= 0.5) {
        for (std::size_t i = 0; i < n3; ++i) trial[i] = x[i] + fraction * step[i];
        const double after_j = potential_j(p, trial, load);
        if (std::isfinite(after_j) &&
            (!held_in_place || after_j < before_j || free_residual_norm(p, trial, load) < before_n))
          break;
      }
      if (halvings == kMaxHalvings)
        return field_error("the line search failed at increment " + std::to_string(increment), "load_increments");
      x = trial;
      ++solution.newton_iterations;
    }
    if (!converged)
      return field_error("Newton did not converge at increment " + std::to_string(increment), "max_newton_iterations");
  }
  solution.reaction_forces_n.assign(n3, 0.0);
  for (std::size_t i = 0; i < n3; ++i)
    if (p.free_of[i] < 0) solution.reaction_forces_n[i] = -residual[i];
  return solution;
}

}  // namespace nav
