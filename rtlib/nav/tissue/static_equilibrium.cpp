#include "nav/tissue/static_equilibrium.hpp"

#include <Eigen/Dense>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <span>
#include <string>

#include "nav/tissue/neo_hookean.hpp"
#include "nav/tissue/newton_static.hpp"
#include "nav/tissue/st_venant_kirchhoff.hpp"
#include "nav/tissue/tet_fem_model.hpp"
#include "nav/tissue/tet_fem_tables.hpp"
#include "nav/tissue/tissue_loads.hpp"
#include "nav/tissue/von_mises.hpp"

namespace nav {
namespace {

using detail::TetFemTables;
using Gradients = Eigen::Map<const Eigen::Matrix<double, 4, 3, Eigen::RowMajor>>;

Error options_error(std::string message) {
  return Error{.message = std::move(message), .field = "static_solve_options"};
}

/// The law of the Newton solve that solves `law`, when Newton takes the case: every law but
/// the corotational, under dead loads (springs and the probe load the tissue model's steps).
std::optional<NewtonLaw> newton_law_of(StaticLaw law, const TissueScene& scene, const TissueInputs& loads) {
  const bool dead_loads = scene.spring_nodes.empty() && !loads.probe.active;
  switch (law) {
    case StaticLaw::linear:
      return dead_loads ? std::optional(NewtonLaw::linear) : std::nullopt;
    case StaticLaw::st_venant_kirchhoff:
      return dead_loads ? std::optional(NewtonLaw::st_venant_kirchhoff) : std::nullopt;
    case StaticLaw::neo_hookean:
      return NewtonLaw::neo_hookean;  // which refuses the others
    case StaticLaw::corotational:
      return std::nullopt;
  }
  return std::nullopt;
}

/// The tissue model whose quasi-static steps solve `law`.
TissueSolverOptions model_options(StaticLaw law, const StaticSolveOptions& options) {
  TissueSolverOptions o;
  o.integrator = Integrator::quasi_static;
  o.solver = LinearSolver::ldlt_warped;
  o.cg_iterations = 20;
  o.rotation = law == StaticLaw::corotational ? ElementRotation::corotational : ElementRotation::none;
  o.law = law == StaticLaw::st_venant_kirchhoff ? ElementLaw::st_venant_kirchhoff : ElementLaw::linear_elastic;
  o.rayleigh_mass_per_s = law == StaticLaw::linear ? 0.0 : options.relaxation_per_s;  // linear: exact in one step
  return o;
}

/// The rotation of F's polar decomposition F = R U, from its singular value decomposition.
Eigen::Matrix3d svd_polar_rotation(const Eigen::Matrix3d& f) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(f, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d u = svd.matrixU();
  if ((u * svd.matrixV().transpose()).determinant() < 0.0) u.col(2) = -u.col(2);
  return u * svd.matrixV().transpose();
}

/// First Piola-Kirchhoff stress of `law` at F, in Pa.
Eigen::Matrix3d first_piola(StaticLaw law, const Eigen::Matrix3d& f, const LameParameters& lame) {
  switch (law) {
    case StaticLaw::linear:
      return hooke_stress(f - Eigen::Matrix3d::Identity(), lame);
    case StaticLaw::corotational: {
      const Eigen::Matrix3d r = svd_polar_rotation(f);
      return r * hooke_stress(r.transpose() * f - Eigen::Matrix3d::Identity(), lame);
    }
    case StaticLaw::st_venant_kirchhoff:
      return stvk_stress(f, lame, 0.0);
    case StaticLaw::neo_hookean:
      return neo_hookean_stress(f, NeoHookeanKinematics(f), lame);
  }
  return Eigen::Matrix3d::Zero();
}

/// Fills the answer's out-of-balance force, reactions and stresses at positions `x`; an Error
/// when an element is inverted there.
Status evaluate(const TetFemTables& tables, StaticLaw law, const TissueInputs& loads, std::span<const double> x,
                StaticEquilibrium& answer) {
  const std::size_t n3 = x.size();
  std::vector<double> force_n(n3, 0.0);
  TissueStepReport unused;
  detail::add_external_forces(tables, loads, x, force_n, unused);
  answer.cauchy_stress_pa.assign(6 * tables.tets.size(), 0.0);
  answer.von_mises_stress_pa.assign(tables.tets.size(), 0.0);
  for (std::size_t e = 0; e < tables.tets.size(); ++e) {
    const Gradients g(tables.gradients.data() + 12 * e);
    Eigen::Matrix<double, 3, 4> corners;
    for (int a = 0; a < 4; ++a)
      for (int i = 0; i < 3; ++i) corners(i, a) = x[3 * static_cast<std::size_t>(tables.tets[e][a]) + i];
    const Eigen::Matrix3d f = corners * g;
    const double j = f.determinant();
    if (!(j > 0.0))
      return Error{.message = "element " + std::to_string(e) + " is inverted at the answer", .field = "law"};
    const Eigen::Matrix3d p = first_piola(law, f, tables.lame[e]);
    const Eigen::Matrix<double, 3, 4> elastic_n = -tables.volume_m3[e] * p * g.transpose();
    for (int a = 0; a < 4; ++a)
      for (int i = 0; i < 3; ++i) force_n[3 * static_cast<std::size_t>(tables.tets[e][a]) + i] += elastic_n(i, a);
    const Eigen::Matrix3d s = law == StaticLaw::linear ? p : Eigen::Matrix3d(p * f.transpose() / j);
    double* out = &answer.cauchy_stress_pa[6 * e];
    out[0] = s(0, 0), out[1] = s(1, 1), out[2] = s(2, 2), out[3] = s(0, 1), out[4] = s(1, 2), out[5] = s(0, 2);
    answer.von_mises_stress_pa[e] = von_mises_pa(out);
  }
  answer.out_of_balance_n.assign(n3, 0.0);
  answer.reaction_n.assign(n3, 0.0);
  double free_sq = 0.0, all_sq = 0.0;
  for (std::size_t i = 0; i < n3; ++i) {
    all_sq += force_n[i] * force_n[i];
    if (tables.node_kind[i / 3] == detail::NodeKind::free) {
      answer.out_of_balance_n[i] = force_n[i];
      free_sq += force_n[i] * force_n[i];
    } else {
      answer.reaction_n[i] = -force_n[i];
    }
  }
  answer.relative_out_of_balance = std::sqrt(free_sq / std::max(all_sq, 1e-300));
  answer.displacement_m.resize(n3);
  for (std::size_t i = 0; i < n3; ++i) answer.displacement_m[i] = x[i] - tables.rest_m[i];
  return Done{};
}

/// `loads` with its forces and prescribed displacement times `fraction`.
TissueInputs ramped(const TissueInputs& loads, double fraction) {
  TissueInputs inputs = loads;
  inputs.load_scale *= fraction;
  for (double& component : inputs.prescribed_displacement_m) component *= fraction;
  return inputs;
}

/// Quasi-static steps of the tissue model to equilibrium.
Result<StaticEquilibrium> step_to_equilibrium(const TetFemModel& model, StaticLaw law, const TissueInputs& loads,
                                              const StaticSolveOptions& options) {
  auto data = make_tet_fem_data(model);
  if (!data.ok()) return data.error();
  TetFemData& d = data.value();
  const int ramp_steps = law == StaticLaw::linear ? 1 : options.ramp_steps;
  StaticEquilibrium answer;
  for (int s = 1; s <= options.max_steps; ++s) {
    step(model, d, ramped(loads, std::min(1.0, static_cast<double>(s) / ramp_steps)));
    if (d.health.has(HealthFlag::bad_sample)) return Error{.message = "the loads were refused", .field = "loads"};
    if (d.health.has(HealthFlag::non_finite_state))
      return Error{.message = "the solve diverged at step " + std::to_string(s), .field = "law"};
    if (s < ramp_steps) continue;
    if (d.report.inverted_elements > 0) continue;  // not an answer yet; the relaxation may recover
    if (Status evaluated = evaluate(model.tables(), law, loads, d.positions_m, answer); !evaluated)
      return evaluated.error();
    answer.iterations = s;
    if (answer.relative_out_of_balance <= options.relative_tolerance) return answer;
  }
  char reached[64];
  std::snprintf(reached, sizeof(reached), "%.3g", answer.relative_out_of_balance);
  return Error{.message = "no equilibrium within " + std::to_string(options.max_steps) +
                          " steps: relative out-of-balance force " + reached,
               .field = "max_steps"};
}

}  // namespace

const char* static_law_name(StaticLaw law) {
  switch (law) {
    case StaticLaw::linear:
      return "linear";
    case StaticLaw::corotational:
      return "corotational";
    case StaticLaw::st_venant_kirchhoff:
      return "stvk";
    case StaticLaw::neo_hookean:
      return "neo-hookean";
  }
  return "unknown";
}

Result<StaticEquilibrium> solve_static(const TetMesh& mesh, const TissueScene& scene, const TissueInputs& loads,
                                       StaticLaw law, const StaticSolveOptions& options) {
  if (!(options.relative_tolerance > 0.0) || options.ramp_steps < 1 || options.max_steps < options.ramp_steps ||
      !(options.relaxation_per_s >= 0.0))
    return options_error("tolerance and relaxation must be positive, and max_steps at least ramp_steps");
  const std::optional<NewtonLaw> newton_law = newton_law_of(law, scene, loads);
  if (!newton_law) {
    auto model = make_tet_fem_model(mesh, scene, model_options(law, options));
    if (!model.ok()) return model.error();
    return step_to_equilibrium(model.value(), law, loads, options);
  }
  auto tables = detail::make_tet_fem_tables(mesh, scene, TissueSolverOptions{});
  if (!tables.ok()) return tables.error();
  NewtonStaticOptions newton;
  newton.law = *newton_law;
  newton.relative_tolerance = options.relative_tolerance;
  auto solved = solve_newton_static(mesh, scene, loads, {}, newton);
  if (!solved.ok()) return solved.error();
  StaticEquilibrium answer;
  if (Status evaluated = evaluate(*tables.value(), law, loads, solved.value().positions_m, answer); !evaluated)
    return evaluated.error();
  answer.iterations = solved.value().newton_iterations;
  return answer;
}

}  // namespace nav
