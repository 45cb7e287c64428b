#include "nav/tissue/newton_static.hpp"

#include <Eigen/Sparse>
#include <algorithm>
#include <array>
#include <cmath>
#include <string>

#include "nav/tissue/neo_hookean.hpp"
#include "nav/tissue/sparse_cholesky.hpp"
#include "nav/tissue/st_venant_kirchhoff.hpp"
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
  NewtonLaw law;
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

/// One element's law at its deformation gradient F: the energy density, the first
/// Piola-Kirchhoff stress and its derivative along dF, with what they share computed once.
class LawAt {
 public:
  LawAt(NewtonLaw law, const Eigen::Matrix3d& f, const LameParameters& lame)
      : law_(law),
        f_(f),
        lame_(lame),
        second_piola_(law == NewtonLaw::st_venant_kirchhoff ? stvk_second_piola(f, lame) : Eigen::Matrix3d::Zero()),
        neo_hookean_(law == NewtonLaw::neo_hookean ? f : Eigen::Matrix3d::Identity()) {}

  /// J/m^3; +infinity for an inverted element under the neo-Hookean law.
  double energy_density() const {
    switch (law_) {
      case NewtonLaw::linear:
        return quadratic_energy_density(0.5 * (f_ + f_.transpose()) - Eigen::Matrix3d::Identity());
      case NewtonLaw::st_venant_kirchhoff:
        return quadratic_energy_density(green_strain(f_));
      case NewtonLaw::neo_hookean:
        return neo_hookean_energy_density(f_, lame_);
    }
    return HUGE_VAL;
  }

  Eigen::Matrix3d stress() const {
    switch (law_) {
      case NewtonLaw::linear:
        return hooke_stress(f_ - Eigen::Matrix3d::Identity(), lame_);
      case NewtonLaw::st_venant_kirchhoff:
        return f_ * second_piola_;
      case NewtonLaw::neo_hookean:
        return neo_hookean_stress(f_, neo_hookean_, lame_);
    }
    return Eigen::Matrix3d::Zero();
  }

  /// The exact derivative (StVK's with its own S, not the positive part the implicit steps take).
  Eigen::Matrix3d derivative(const Eigen::Matrix3d& df) const {
    switch (law_) {
      case NewtonLaw::linear:
        return hooke_stress(df, lame_);
      case NewtonLaw::st_venant_kirchhoff:
        return stvk_stress_derivative(f_, df, second_piola_, lame_, 0.0);
      case NewtonLaw::neo_hookean:
        return neo_hookean_stress_derivative(neo_hookean_, df, lame_);
    }
    return Eigen::Matrix3d::Zero();
  }

 private:
  /// mu e:e + lambda/2 tr(e)^2 of a symmetric strain e.
  double quadratic_energy_density(const Eigen::Matrix3d& strain) const {
    return lame_.mu_pa * strain.squaredNorm() + 0.5 * lame_.lambda_pa * strain.trace() * strain.trace();
  }

  NewtonLaw law_;
  Eigen::Matrix3d f_;
  LameParameters lame_;
  Eigen::Matrix3d second_piola_;
  NeoHookeanKinematics neo_hookean_;
};

/// Elastic energy minus the work of the dead loads (scaled by `load`), +inf if an element inverts
/// under a law that forbids it.
double potential_j(const Problem& p, std::span<const double> x, double load) {
  double energy_j = 0.0;
  for (std::size_t e = 0; e < p.tables.tets.size(); ++e)
    energy_j += p.tables.volume_m3[e] * LawAt(p.law, deformation_gradient(p, e, x), p.tables.lame[e]).energy_density();
  for (std::size_t i = 0; i < x.size(); ++i) energy_j -= load * p.dead_load_n[i] * (x[i] - p.rest_m[i]);
  return energy_j;
}

/// Adds the elastic restoring forces at x to `residual` (3 per node).
void add_elastic_forces(const Problem& p, std::span<const double> x, std::vector<double>& residual) {
  for (std::size_t e = 0; e < p.tables.tets.size(); ++e) {
    const Eigen::Matrix<double, 3, 4> forces = -p.tables.volume_m3[e] *
                                               LawAt(p.law, deformation_gradient(p, e, x), p.tables.lame[e]).stress() *
                                               Gradients(p.tables.gradients.data() + 12 * e).transpose();
    for (int a = 0; a < 4; ++a)
      for (int i = 0; i < 3; ++i) residual[3 * static_cast<std::size_t>(p.tables.tets[e][a]) + i] += forces(i, a);
  }
}

/// The tangent's lower triangle over free dofs in a pattern built once, and where each
/// element's entries go in it (-1: a held dof or the upper triangle), 144 per element.
struct TangentPattern {
  Eigen::SparseMatrix<double> matrix;
  std::vector<std::int32_t> slot;
};

/// The element's 12 dofs, node by node.
std::array<std::size_t, 12> element_dofs(const Problem& p, std::size_t e) {
  std::array<std::size_t, 12> dof{};
  for (int a = 0; a < 4; ++a)
    for (int i = 0; i < 3; ++i) dof[3 * a + i] = 3 * static_cast<std::size_t>(p.tables.tets[e][a]) + i;
  return dof;
}

TangentPattern make_tangent_pattern(const Problem& p) {
  std::vector<Eigen::Triplet<double>> triplets;
  for (std::size_t e = 0; e < p.tables.tets.size(); ++e) {
    const auto dof = element_dofs(p, e);
    for (std::size_t column = 0; column < 12; ++column)
      for (std::size_t row = 0; row < 12; ++row)
        if (p.free_of[dof[column]] >= 0 && p.free_of[dof[row]] >= p.free_of[dof[column]])
          triplets.emplace_back(p.free_of[dof[row]], p.free_of[dof[column]], 0.0);
  }
  TangentPattern pattern;
  pattern.matrix.resize(p.free_count, p.free_count);
  pattern.matrix.setFromTriplets(triplets.begin(), triplets.end());
  pattern.matrix.makeCompressed();
  const std::int32_t* starts = pattern.matrix.outerIndexPtr();
  const std::int32_t* rows = pattern.matrix.innerIndexPtr();
  pattern.slot.assign(144 * p.tables.tets.size(), -1);
  for (std::size_t e = 0; e < p.tables.tets.size(); ++e) {
    const auto dof = element_dofs(p, e);
    for (std::size_t column = 0; column < 12; ++column)
      for (std::size_t row = 0; row < 12; ++row) {
        const std::int32_t c = p.free_of[dof[column]], r = p.free_of[dof[row]];
        if (c < 0 || r < c) continue;
        pattern.slot[144 * e + 12 * column + row] =
            static_cast<std::int32_t>(std::lower_bound(rows + starts[c], rows + starts[c + 1], r) - rows);
      }
  }
  return pattern;
}

/// Out-of-balance forces (elastic restoring + dead loads) on every dof, the tangent stiffness
/// over free dofs into `tangent`'s values, and tangent * step restricted to held dofs, moved to
/// the free rows.
void linearise(const Problem& p, std::span<const double> x, double load, std::span<const double> held_step,
               std::vector<double>& residual, TangentPattern& tangent, std::vector<double>& held_coupling) {
  for (std::size_t i = 0; i < residual.size(); ++i) residual[i] = load * p.dead_load_n[i];
  std::fill(held_coupling.begin(), held_coupling.end(), 0.0);
  double* values = tangent.matrix.valuePtr();
  std::fill(values, values + tangent.matrix.nonZeros(), 0.0);
  for (std::size_t e = 0; e < p.tables.tets.size(); ++e) {
    const Gradients g(p.tables.gradients.data() + 12 * e);
    const LawAt law(p.law, deformation_gradient(p, e, x), p.tables.lame[e]);
    const double volume_m3 = p.tables.volume_m3[e];
    const Eigen::Matrix<double, 3, 4> forces = -volume_m3 * law.stress() * g.transpose();
    const auto dof = element_dofs(p, e);
    for (int a = 0; a < 4; ++a)
      for (int i = 0; i < 3; ++i) residual[dof[3 * a + i]] += forces(i, a);
    for (int column = 0; column < 12; ++column) {
      Eigen::Matrix3d df = Eigen::Matrix3d::Zero();
      df.row(column % 3) = g.row(column / 3);
      const Eigen::Matrix<double, 3, 4> k_column = volume_m3 * law.derivative(df) * g.transpose();
      const bool held_column = p.free_of[dof[column]] < 0;
      for (int row = 0; row < 12; ++row) {
        const std::int32_t free_row = p.free_of[dof[row]];
        if (free_row < 0) continue;
        const double k = k_column(row % 3, row / 3);
        if (held_column)
          held_coupling[static_cast<std::size_t>(free_row)] += k * held_step[dof[column]];
        else if (const std::int32_t slot = tangent.slot[144 * e + 12 * column + row]; slot >= 0)
          values[slot] += k;
      }
    }
  }
}

/// |out-of-balance force| over free dofs at x: a descent test that, unlike the potential,
/// keeps its precision close to equilibrium.
double free_residual_norm(const Problem& p, std::span<const double> x, double load) {
  std::vector<double> residual(x.size());
  for (std::size_t i = 0; i < residual.size(); ++i) residual[i] = load * p.dead_load_n[i];
  add_elastic_forces(p, x, residual);
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

Result<Problem> make_problem(const TetFemTables& tables, NewtonLaw law, const TissueInputs& loads,
                             std::span<const DofConstraint> constraints) {
  Problem p{tables, law, tables.rest_m, {}, {}, {}, 0};
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

/// Newton iterations at `load` from x; false when the line search fails or max_newton_iterations
/// steps leave it unconverged.
bool converge(const Problem& p, const NewtonStaticOptions& options, double load, TangentPattern& tangent,
              SparseCholesky& factor, NewtonStaticSolution& solution, std::vector<double>& residual) {
  std::vector<double>& x = solution.positions_m;
  const std::size_t n3 = x.size();
  std::vector<double> held_coupling(static_cast<std::size_t>(p.free_count)), step(n3), trial(n3);
  Eigen::VectorXd rhs(p.free_count);
  for (int iteration = 0;; ++iteration) {
    for (std::size_t i = 0; i < n3; ++i)
      step[i] = p.free_of[i] < 0 ? p.rest_m[i] + load * p.held_target_m[i] - x[i] : 0.0;
    linearise(p, x, load, step, residual, tangent, held_coupling);
    const bool held_in_place = norm(step) == 0.0;
    double free_norm = 0.0, scale = 0.0;
    for (std::size_t i = 0; i < n3; ++i) {
      scale += residual[i] * residual[i];
      if (p.free_of[i] >= 0) free_norm += residual[i] * residual[i];
    }
    solution.relative_residual = std::sqrt(free_norm / std::max(scale, 1e-300));
    if (held_in_place && solution.relative_residual <= options.relative_tolerance) return true;
    if (iteration == options.max_newton_iterations || !factor.factor(tangent.matrix, "tangent").ok()) return false;
    for (std::size_t i = 0; i < n3; ++i)
      if (p.free_of[i] >= 0) rhs[p.free_of[i]] = residual[i] - held_coupling[static_cast<std::size_t>(p.free_of[i])];
    const Eigen::VectorXd free_step = factor.solve(rhs);
    for (std::size_t i = 0; i < n3; ++i)
      if (p.free_of[i] >= 0) step[i] = free_step[p.free_of[i]];
    // Line search: no element inverted where the law forbids it, and (once the held dofs are
    // in place) a lower potential or a smaller out-of-balance force.
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
    if (halvings == kMaxHalvings) return false;
    x = trial;
    ++solution.newton_iterations;
  }
}

}  // namespace

Result<NewtonStaticSolution> solve_newton_static(const TetMesh& mesh, const TissueScene& scene,
                                                 const TissueInputs& loads, std::span<const DofConstraint> constraints,
                                                 const NewtonStaticOptions& options) {
  if (loads.probe.active)
    return field_error("the Newton solve does not model the probe: prescribe the pressed nodes", "probe");
  if (!scene.spring_nodes.empty()) return field_error("the Newton solve does not model frame springs", "spring_nodes");
  if (options.load_increments < 1 || options.max_cutbacks < 0 || options.max_newton_iterations < 1 ||
      !(options.relative_tolerance > 0.0))
    return field_error("increments, iterations and tolerance must be positive", "options");
  auto tables = detail::make_tet_fem_tables(mesh, scene, TissueSolverOptions{});
  if (!tables.ok()) return tables.error();
  auto problem = make_problem(*tables.value(), options.law, loads, constraints);
  if (!problem.ok()) return problem.error();
  const Problem& p = problem.value();
  TangentPattern tangent = make_tangent_pattern(p);
  SparseCholesky factor;
  NewtonStaticSolution solution;
  solution.positions_m = p.rest_m;
  std::vector<double> residual(p.rest_m.size()), converged_m = p.rest_m;
  // Load fractions in units of the smallest increment the cutbacks can reach, so that they add up exactly.
  const std::int64_t whole = static_cast<std::int64_t>(options.load_increments) << options.max_cutbacks;
  std::int64_t done = 0, increment = std::int64_t{1} << options.max_cutbacks;
  while (done < whole) {
    const std::int64_t next = std::min(whole, done + increment);
    if (converge(p, options, static_cast<double>(next) / static_cast<double>(whole), tangent, factor, solution,
                 residual)) {
      done = next;
      converged_m = solution.positions_m;
      continue;
    }
    if (solution.cutbacks == options.max_cutbacks)
      return field_error("Newton did not converge at load fraction " +
                             std::to_string(static_cast<double>(next) / static_cast<double>(whole)) + " after " +
                             std::to_string(options.max_cutbacks) + " cutbacks",
                         "max_cutbacks");
    ++solution.cutbacks;
    increment /= 2;
    solution.positions_m = converged_m;
  }
  solution.reaction_forces_n.assign(p.rest_m.size(), 0.0);
  for (std::size_t i = 0; i < p.rest_m.size(); ++i)
    if (p.free_of[i] < 0) solution.reaction_forces_n[i] = -residual[i];
  return solution;
}

}  // namespace nav
