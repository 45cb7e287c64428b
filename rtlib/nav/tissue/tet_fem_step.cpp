// Step-time integrators of a TetFemModel: implicit Euler, quasi-static and explicit central
// difference, and the energy diagnostics.
#include <algorithm>
#include <cmath>

#include "nav/core/finite.hpp"
#include "nav/tissue/explicit_update.hpp"
#include "nav/tissue/linear_solve.hpp"
#include "nav/tissue/tet_fem_kernels.hpp"
#include "nav/tissue/tet_fem_model.hpp"
#include "nav/tissue/tet_fem_tables.hpp"
#include "nav/tissue/tissue_loads.hpp"

namespace nav {
namespace {

using detail::TetFemTables;

/// Forces at the current positions: external loads plus elastic restoring forces, after
/// the element rotations are brought up to date (inverted elements flagged).
void compute_forces(const TetFemTables& tables, TetFemData& data, const TissueInputs& inputs) {
  data.report.inverted_elements = detail::update_element_rotations(tables, data.positions_m, data.element_rotations);
  if (data.report.inverted_elements > 0) data.health.raise(HealthFlag::inverted_element);
  std::fill(data.forces_n.begin(), data.forces_n.end(), 0.0);
  detail::add_external_forces(tables, inputs, data.positions_m, data.forces_n, data.report);
  detail::add_elastic_forces(tables, data.positions_m, data.element_rotations, data.forces_n);
  if (tables.options.integrator != Integrator::explicit_central_difference)
    detail::update_tangent_stresses(tables, data.positions_m, data.tangent_stresses);
}

/// A dv = h (f - a M v) - (h b + h^2) K_R v - h^2 Ks v, then v += dv, x += h v.
void implicit_euler(const TetFemTables& tables, TetFemData& data) {
  const TissueSolverOptions& o = tables.options;
  const double h = o.step_s;
  const std::span<double> v_free = data.direction;
  std::copy(data.velocities_m_s.begin(), data.velocities_m_s.end(), v_free.begin());
  detail::zero_constrained(tables, v_free);
  for (std::size_t i = 0; i < data.rhs.size(); ++i)
    data.rhs[i] = h * (data.forces_n[i] - o.rayleigh_mass_per_s * tables.mass_kg[i / 3] * data.velocities_m_s[i]);
  detail::add_stiffness_product(tables, data.positions_m, data.element_rotations, data.tangent_stresses, v_free,
                                -(h * o.rayleigh_stiffness_s + h * h), data.rhs);
  detail::add_spring_product(tables, v_free, -h * h, data.rhs);
  detail::zero_constrained(tables, data.rhs);
  detail::solve_system(tables, data);
  for (std::int32_t node : tables.free_nodes)
    for (int c = 0; c < 3; ++c) {
      const std::size_t i = 3 * static_cast<std::size_t>(node) + c;
      data.velocities_m_s[i] += data.solution[i];
      data.positions_m[i] += h * data.velocities_m_s[i];
    }
}

/// (K_R + Ks + a/h M + b/h K_R) du = f, then x += du; the velocity reported is du / h. The
/// Rayleigh terms are the damping forces of the motion du over the step: they leave the
/// equilibrium unchanged and keep the iteration from overshooting where the corotational
/// tangent (which leaves out the derivative of the rotations) is far from the exact one.
void quasi_static(const TetFemTables& tables, TetFemData& data) {
  std::copy(data.forces_n.begin(), data.forces_n.end(), data.rhs.begin());
  detail::zero_constrained(tables, data.rhs);
  detail::solve_system(tables, data);
  const double inverse_step = 1.0 / tables.options.step_s;
  for (std::int32_t node : tables.free_nodes)
    for (int c = 0; c < 3; ++c) {
      const std::size_t i = 3 * static_cast<std::size_t>(node) + c;
      data.positions_m[i] += data.solution[i];
      data.velocities_m_s[i] = data.solution[i] * inverse_step;
    }
}

/// Central difference with velocities at half steps (detail::central_difference_update).
void central_difference(const TetFemTables& tables, TetFemData& data) {
  const double h = tables.options.step_s;
  detail::central_difference_update(tables, data.forces_n, h, tables.options.rayleigh_mass_per_s, data.positions_m,
                                    data.velocities_m_s);
  data.report.solver_iterations = 0;
  data.report.solver_relative_residual = 0.0;
  if (h > tables.stable_step_s) data.health.raise(HealthFlag::unstable_step);
}

}  // namespace

void step(const TetFemModel& model, TetFemData& data, const TissueInputs& inputs) noexcept {
  const TetFemTables& tables = model.tables();
  if (!detail::inputs_are_valid(tables, inputs)) {
    data.health.raise(HealthFlag::bad_sample);
    return;
  }
  std::copy(data.positions_m.begin(), data.positions_m.end(), data.backup_positions_m.begin());
  std::copy(data.velocities_m_s.begin(), data.velocities_m_s.end(), data.backup_velocities_m_s.begin());
  detail::move_kinematic_nodes(tables, inputs, tables.options.step_s, data.positions_m, data.velocities_m_s);
  compute_forces(tables, data, inputs);
  switch (tables.options.integrator) {
    case Integrator::implicit_euler:
      implicit_euler(tables, data);
      break;
    case Integrator::quasi_static:
      quasi_static(tables, data);
      break;
    case Integrator::explicit_central_difference:
      central_difference(tables, data);
      break;
  }
  if (!all_finite(data.positions_m) || !all_finite(data.velocities_m_s)) {
    std::copy(data.backup_positions_m.begin(), data.backup_positions_m.end(), data.positions_m.begin());
    std::copy(data.backup_velocities_m_s.begin(), data.backup_velocities_m_s.end(), data.velocities_m_s.begin());
    data.health.raise(HealthFlag::non_finite_state);
    return;
  }
  ++data.steps;
}

void copy_state(const TetFemData& from, TetFemData& to) noexcept {
  std::copy(from.positions_m.begin(), from.positions_m.end(), to.positions_m.begin());
  std::copy(from.velocities_m_s.begin(), from.velocities_m_s.end(), to.velocities_m_s.begin());
  std::copy(from.element_rotations.begin(), from.element_rotations.end(), to.element_rotations.begin());
  to.report = from.report;
  to.steps = from.steps;
  to.health.clear_all();
}

double elastic_energy_j(const TetFemModel& model, const TetFemData& data) noexcept {
  return detail::elastic_energy(model.tables(), data.positions_m);
}

double kinetic_energy_j(const TetFemModel& model, const TetFemData& data) noexcept {
  double energy_j = 0.0;
  for (std::size_t i = 0; i < data.velocities_m_s.size(); ++i)
    energy_j += 0.5 * model.tables().mass_kg[i / 3] * data.velocities_m_s[i] * data.velocities_m_s[i];
  return energy_j;
}

double gravity_energy_j(const TetFemModel& model, const TetFemData& data) noexcept {
  const TetFemTables& tables = model.tables();
  double energy_j = 0.0;
  for (std::size_t i = 0; i < data.positions_m.size(); ++i)
    energy_j -= tables.mass_kg[i / 3] * tables.gravity_m_s2[i % 3] * data.positions_m[i];
  return energy_j;
}

}  // namespace nav
