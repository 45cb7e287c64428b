// Step-time integrators of a ReducedModel (implicit Euler and quasi-static Newton
// iterations on the r x r system), its envelope check, its error estimate and the lazy
// reconstruction.
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

#include "nav/core/finite.hpp"
#include "nav/reduced/dense_cholesky.hpp"
#include "nav/reduced/reduced_envelope.hpp"
#include "nav/reduced/reduced_forces.hpp"
#include "nav/reduced/reduced_kernels.hpp"
#include "nav/reduced/reduced_model.hpp"
#include "nav/reduced/reduced_tables.hpp"

namespace nav {
namespace {

using detail::ReducedTables;

bool finite_point(const Point3& p) { return std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]); }

bool inputs_are_valid(const ReducedTables& t, const TissueInputs& inputs) {
  if (!std::isfinite(inputs.load_scale) || !finite_point(inputs.traction_pa) ||
      !finite_point(inputs.prescribed_displacement_m) || !finite_point(inputs.spring_frame.translation_m))
    return false;
  if (inputs.point_forces.size() > t.max_point_forces) return false;
  for (const PointForce& force : inputs.point_forces)
    if (force.node < 0 || force.node >= t.node_count || !finite_point(force.force_n)) return false;
  double norm_squared = 0.0;
  for (double value : inputs.spring_frame.rotation_wxyz) {
    if (!std::isfinite(value)) return false;
    norm_squared += value * value;
  }
  return norm_squared > 0.0;
}

/// out += U_node^T v (the node's 3 x r basis rows).
void add_node_force(const ReducedTables& t, std::int64_t node, const double v[3], std::span<double> out) {
  const int r = t.r;
  const double* rows = t.rows.data() + 3 * static_cast<std::size_t>(node) * static_cast<std::size_t>(r);
  for (int c = 0; c < 3; ++c)
    for (int j = 0; j < r; ++j) out[static_cast<std::size_t>(j)] += rows[c * r + j] * v[c];
}

/// External reduced force: gravity, point forces and traction (times load_scale), and the
/// frame springs' pull towards their moved anchors (less their -k U_s^T U_s q part, which is
/// in the tangent).
void external_force(const ReducedTables& t, const TissueInputs& inputs, const double d[3], std::span<double> out) {
  const int r = t.r;
  const double scale = inputs.load_scale;
  for (int j = 0; j < r; ++j) {
    double value = t.gravity_r[static_cast<std::size_t>(j)];
    for (int c = 0; c < 3; ++c) value += t.traction_r[static_cast<std::size_t>(c * r + j)] * inputs.traction_pa[c];
    out[static_cast<std::size_t>(j)] = scale * value;
  }
  for (const PointForce& force : inputs.point_forces) {
    const double v[3] = {scale * force.force_n[0], scale * force.force_n[1], scale * force.force_n[2]};
    add_node_force(t, force.node, v, out);
  }
  if (t.spring_nodes.empty()) return;
  const auto& w = inputs.spring_frame.rotation_wxyz;
  const Eigen::Matrix3d rotation = Eigen::Quaterniond(w[0], w[1], w[2], w[3]).normalized().toRotationMatrix();
  for (std::size_t k = 0; k < t.spring_nodes.size(); ++k) {
    const std::int64_t node = t.spring_nodes[k];
    const double* rest = t.spring_rest_m.data() + 3 * k;
    double pull[3];
    for (int c = 0; c < 3; ++c) {
      double anchor = inputs.spring_frame.translation_m[c];
      for (int j = 0; j < 3; ++j) anchor += rotation(c, j) * rest[j];
      double lifted = 0.0;
      if (t.has_lift)
        for (int j = 0; j < 3; ++j) lifted += t.lift_rows[9 * static_cast<std::size_t>(node) + 3 * c + j] * d[j];
      pull[c] = t.spring_stiffness_n_m * (anchor - rest[c] - lifted);
    }
    add_node_force(t, node, pull, out);
  }
}

/// Row i of a x (a r x r row-major).
double product_row(std::span<const double> a, std::span<const double> x, int r, int i) {
  return detail::dot(a.data() + i * r, x.data(), r);
}

double norm(std::span<const double> v) {
  double sum = 0.0;
  for (double value : v) sum += value * value;
  return std::sqrt(sum);
}

/// The elastic tangent of a Newton iteration and the factor of its system matrix.
struct NewtonSystem {
  std::span<const double> tangent, factor;
};

/// Force (external + internal - springs' U_s^T U_s q) at q and, when rebuilding, the elastic
/// tangent into data.tangent; returns the tangent and the system factor to use (the rest ones
/// when frozen).
NewtonSystem forces_and_factor(const ReducedTables& t, ReducedData& data, std::span<const double> q,
                               const double d[3]) {
  const int r = t.r;
  // Outside the training envelope the rest tangent may be far from the current one (a frozen
  // Newton iteration then diverges at long steps): the tangent is rebuilt there.
  const bool rebuild =
      (!t.options.frozen_tangent || data.report.out_of_envelope) && t.force_kind != ReducedForceKind::linear;
  const detail::ReducedState state{q, d};
  const detail::ForceScratch scratch{data.sample_displacements, data.sample_rotations, data.sample_tangent_rows,
                                     data.monomials};
  const int inverted =
      detail::evaluate_internal_force(t, state, scratch, data.force, rebuild ? data.tangent : std::span<double>{});
  data.report.inverted_samples = std::max(data.report.inverted_samples, inverted);
  const bool springs = !t.spring_nodes.empty();  // else U_s^T U_s is zero
  for (int i = 0; i < r; ++i) {
    double applied = data.external[static_cast<std::size_t>(i)];
    if (springs) applied -= product_row(t.spring_stiffness_r, q, r, i);
    data.force[static_cast<std::size_t>(i)] += applied;
  }
  if (!rebuild) return {t.stiffness_r, t.frozen_factor};
  const detail::SystemCoefficients c = detail::system_coefficients(t.options);
  detail::system_matrix(data.tangent, t.spring_stiffness_r, c.identity, c.stiffness, c.spring, r, data.factor);
  if (detail::cholesky_in_place(data.factor, r)) return {data.tangent, data.factor};
  data.health.raise(HealthFlag::solver_not_converged);  // fall back on the rest factor
  return {data.tangent, t.frozen_factor};
}

/// Newton iterations on (v - v0) = h (f(q0 + h v) - a v - b K v).
void implicit_euler(const ReducedTables& t, ReducedData& data, const double d[3]) {
  const ReducedSolverOptions& o = t.options;
  const int r = t.r;
  const double h = o.step_s;
  std::copy(data.v_start.begin(), data.v_start.end(), data.v_iterate.begin());
  for (int iteration = 0; iteration < o.newton_iterations; ++iteration) {
    for (int i = 0; i < r; ++i)
      data.q[static_cast<std::size_t>(i)] =
          data.q_start[static_cast<std::size_t>(i)] + h * data.v_iterate[static_cast<std::size_t>(i)];
    const NewtonSystem system = forces_and_factor(t, data, data.q, d);
    double scale = 0.0;
    for (int i = 0; i < r; ++i) {
      const auto k = static_cast<std::size_t>(i);
      const double change = data.v_iterate[k] - data.v_start[k];
      const double damping = o.rayleigh_mass_per_s * data.v_iterate[k] +
                             o.rayleigh_stiffness_s * product_row(system.tangent, data.v_iterate, r, i);
      data.residual[k] = h * (data.force[k] - damping) - change;
      scale += h * h * data.force[k] * data.force[k] + change * change;
    }
    data.report.relative_residual = norm(data.residual) / (std::sqrt(scale) + 1e-300);
    std::copy(data.residual.begin(), data.residual.end(), data.correction.begin());
    detail::cholesky_solve(system.factor, r, data.correction);
    for (std::size_t k = 0; k < data.v_iterate.size(); ++k) data.v_iterate[k] += data.correction[k];
  }
  for (int i = 0; i < r; ++i) {
    const auto k = static_cast<std::size_t>(i);
    data.q_velocity[k] = data.v_iterate[k];
    data.q[k] = data.q_start[k] + h * data.v_iterate[k];
  }
}

/// Newton iterations on f(q) - (a / h) (q - q0) - (b / h) K (q - q0) = 0.
void quasi_static(const ReducedTables& t, ReducedData& data, const double d[3]) {
  const ReducedSolverOptions& o = t.options;
  const int r = t.r;
  const double h = o.step_s;
  std::copy(data.q_start.begin(), data.q_start.end(), data.q.begin());
  for (int iteration = 0; iteration < o.newton_iterations; ++iteration) {
    const NewtonSystem system = forces_and_factor(t, data, data.q, d);
    for (int i = 0; i < r; ++i) {
      const auto k = static_cast<std::size_t>(i);
      data.correction[k] = data.q[k] - data.q_start[k];
    }
    for (int i = 0; i < r; ++i) {
      const auto k = static_cast<std::size_t>(i);
      data.residual[k] = data.force[k] - (o.rayleigh_mass_per_s / h) * data.correction[k] -
                         (o.rayleigh_stiffness_s / h) * product_row(system.tangent, data.correction, r, i);
    }
    data.report.relative_residual = norm(data.residual) / (norm(data.force) + norm(data.external) + 1e-300);
    std::copy(data.residual.begin(), data.residual.end(), data.correction.begin());
    detail::cholesky_solve(system.factor, r, data.correction);
    for (std::size_t k = 0; k < data.q.size(); ++k) data.q[k] += data.correction[k];
  }
  for (std::size_t k = 0; k < data.q.size(); ++k) data.q_velocity[k] = (data.q[k] - data.q_start[k]) / h;
}

/// How far beyond its training bound a coordinate may go (in units of envelope_factor times
/// the bound) before it is held there, its velocity zeroed: the model is not trusted there
/// (the flag is up), and an untrained direction must not run away.
constexpr double kSaturation = 10.0;

/// The training envelope check: the largest |q_i| / bound_i, and the saturation.
void check_envelope(const ReducedTables& t, ReducedData& data) {
  for (std::size_t i = 0; i < t.q_bound.size(); ++i) {
    const double limit = kSaturation * t.options.envelope_factor * t.q_bound[i];
    if (std::abs(data.q[i]) <= limit) continue;
    data.q[i] = std::copysign(limit, data.q[i]);
    data.q_velocity[i] = 0.0;
  }
  const double ratio = detail::envelope_ratio(t.q_bound, t.options.envelope_factor, data.q);
  data.report.envelope_ratio = ratio;
  data.report.out_of_envelope = ratio > t.options.envelope_factor;
  if (data.report.out_of_envelope) data.health.raise(HealthFlag::reduced_out_of_envelope);
}

/// The error estimate under `inputs`: the displacement the basis misses under the point
/// forces, gain x the sum over loaded nodes of |M_n f_n| (f_n the node's forces, scaled).
void estimate_error(const ReducedTables& t, ReducedData& data, const TissueInputs& inputs) {
  if (t.missing_compliance.empty()) return;
  const std::span<const PointForce> forces = inputs.point_forces;
  double sum_m = 0.0;
  for (std::size_t i = 0; i < forces.size(); ++i) {
    const std::int32_t node = forces[i].node;
    if (std::any_of(forces.begin(), forces.begin() + static_cast<std::ptrdiff_t>(i),
                    [&](const PointForce& f) { return f.node == node; }))
      continue;  // summed with its first force
    double f[3] = {0.0, 0.0, 0.0};
    for (std::size_t j = i; j < forces.size(); ++j)
      if (forces[j].node == node)
        for (std::size_t c = 0; c < 3; ++c) f[c] += inputs.load_scale * forces[j].force_n[c];
    const double* m = t.missing_compliance.data() + 6 * static_cast<std::size_t>(node);
    const double u[3] = {m[0] * f[0] + m[1] * f[1] + m[2] * f[2], m[1] * f[0] + m[3] * f[1] + m[4] * f[2],
                         m[2] * f[0] + m[4] * f[1] + m[5] * f[2]};
    sum_m += std::sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2]);
  }
  data.report.estimated_error_m = t.error_gain * sum_m;
  data.report.error_over_bound = data.report.estimated_error_m > t.error_bound_m;
  if (data.report.error_over_bound) data.health.raise(HealthFlag::reduced_error_over_bound);
}

}  // namespace

void step(const ReducedModel& model, ReducedData& data, const TissueInputs& inputs) noexcept {
  const ReducedTables& t = model.tables();
  if (!inputs_are_valid(t, inputs)) {
    data.health.raise(HealthFlag::bad_sample);
    return;
  }
  std::copy(data.q.begin(), data.q.end(), data.q_start.begin());
  std::copy(data.q_velocity.begin(), data.q_velocity.end(), data.v_start.begin());
  const double d[3] = {t.has_lift ? inputs.prescribed_displacement_m[0] : 0.0,
                       t.has_lift ? inputs.prescribed_displacement_m[1] : 0.0,
                       t.has_lift ? inputs.prescribed_displacement_m[2] : 0.0};
  data.report.inverted_samples = 0;
  external_force(t, inputs, d, data.external);
  if (t.options.integrator == ReducedIntegrator::implicit_euler)
    implicit_euler(t, data, d);
  else
    quasi_static(t, data, d);
  if (!all_finite(data.q) || !all_finite(data.q_velocity)) {
    std::copy(data.q_start.begin(), data.q_start.end(), data.q.begin());
    std::copy(data.v_start.begin(), data.v_start.end(), data.q_velocity.begin());
    data.health.raise(HealthFlag::non_finite_state);
    return;
  }
  if (data.report.inverted_samples > 0) data.health.raise(HealthFlag::inverted_element);
  std::copy(d, d + 3, data.prescribed_m);
  check_envelope(t, data);
  estimate_error(t, data, inputs);
  ++data.steps;
}

void copy_state(const ReducedData& from, ReducedData& to) noexcept {
  std::copy(from.q.begin(), from.q.end(), to.q.begin());
  std::copy(from.q_velocity.begin(), from.q_velocity.end(), to.q_velocity.begin());
  std::copy(std::begin(from.prescribed_m), std::end(from.prescribed_m), std::begin(to.prescribed_m));
  to.report = from.report;
  to.steps = from.steps;
  to.health.clear_all();
}

void reconstruct_displacements_m(const ReducedModel& model, const ReducedData& data,
                                 std::span<const std::int32_t> nodes, std::span<double> out_xyz) noexcept {
  const ReducedTables& t = model.tables();
  const int r = t.r;
  const std::size_t count = std::min(nodes.size(), out_xyz.size() / 3);
  for (std::size_t k = 0; k < count; ++k) {
    const std::int32_t node = nodes[k];
    if (node < 0 || node >= t.node_count) {
      for (int c = 0; c < 3; ++c) out_xyz[3 * k + static_cast<std::size_t>(c)] = 0.0;
      continue;
    }
    const double* rows = t.rows.data() + 3 * static_cast<std::size_t>(node) * static_cast<std::size_t>(r);
    for (int c = 0; c < 3; ++c) {
      double value = detail::dot(rows + c * r, data.q.data(), r);
      if (t.has_lift)
        for (int j = 0; j < 3; ++j)
          value += t.lift_rows[9 * static_cast<std::size_t>(node) + static_cast<std::size_t>(3 * c + j)] *
                   data.prescribed_m[j];
      out_xyz[3 * k + static_cast<std::size_t>(c)] = value;
    }
  }
}

void reconstruct_all_displacements_m(const ReducedModel& model, const ReducedData& data,
                                     std::span<double> out) noexcept {
  const ReducedTables& t = model.tables();
  const int r = t.r;
  const std::size_t values = std::min(out.size(), 3 * static_cast<std::size_t>(t.node_count));
  for (std::size_t i = 0; i < values; ++i) {
    double value = detail::dot(t.rows.data() + i * static_cast<std::size_t>(r), data.q.data(), r);
    if (t.has_lift)
      for (int j = 0; j < 3; ++j) value += t.lift_rows[3 * i + static_cast<std::size_t>(j)] * data.prescribed_m[j];
    out[i] = value;
  }
}

void reconstruct_display_m(const ReducedModel& model, const ReducedData& data, const ReducedDisplaySet& display,
                           std::span<double> out_xyz) noexcept {
  const std::size_t values = std::min(out_xyz.size(), 3 * display.nodes.size());
  if (display.basis_size != model.basis_size()) return;
  model.tables().lane_kernels->panel_times(
      display.panels.data(), display.lift_panels.empty() ? nullptr : display.lift_panels.data(), data.q.data(),
      display.basis_size, data.prescribed_m, out_xyz.data(), values);
}

}  // namespace nav
