// Step of a MassSpringModel: springs and loads, central difference, then Promayon's volume
// projection x = x^ + lambda G with G the volume gradient on free boundary nodes and lambda
// the root nearest zero of the cubic V(x^ + lambda G) = V0; inverted tetrahedra are flagged.
#include <algorithm>
#include <cmath>

#include "nav/core/finite.hpp"
#include "nav/tissue/explicit_update.hpp"
#include "nav/tissue/mass_spring_model.hpp"
#include "nav/tissue/tet_fem_kernels.hpp"
#include "nav/tissue/tissue_loads.hpp"

namespace nav {
namespace {

using Vector = std::array<double, 3>;

Vector at(std::span<const double> x, std::int32_t node) {
  const std::size_t i = 3 * static_cast<std::size_t>(node);
  return {x[i], x[i + 1], x[i + 2]};
}

Vector cross(const Vector& a, const Vector& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

double dot(const Vector& a, const Vector& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

void add_spring_forces(const MassSpringTables& tables, std::span<const double> x, std::span<double> forces) {
  for (std::size_t s = 0; s < tables.springs.size(); ++s) {
    const auto [i, j] = tables.springs[s];
    const Vector a = at(x, i), b = at(x, j);
    const Vector d{b[0] - a[0], b[1] - a[1], b[2] - a[2]};
    const double length_m = std::sqrt(dot(d, d));
    if (!(length_m > 0.0)) continue;  // collapsed spring: no direction to push along
    const double scale = tables.stiffness_n_m[s] * (length_m - tables.rest_length_m[s]) / length_m;
    for (int c = 0; c < 3; ++c) {
      forces[3 * static_cast<std::size_t>(i) + c] += scale * d[c];
      forces[3 * static_cast<std::size_t>(j) + c] -= scale * d[c];
    }
  }
}

/// Moves the free boundary nodes along the volume gradient so that the enclosed volume
/// returns to rest; returns the displacement's multiplier.
double project_volume(const MassSpringTables& tables, std::span<double> x, std::span<double> gradient) {
  std::fill(gradient.begin(), gradient.end(), 0.0);
  for (const auto& t : tables.boundary_triangles) {  // grad_a V = (b x c) / 6, cyclically
    for (int k = 0; k < 3; ++k) {
      const Vector g = cross(at(x, t[(k + 1) % 3]), at(x, t[(k + 2) % 3]));
      for (int c = 0; c < 3; ++c) gradient[3 * static_cast<std::size_t>(t[k]) + c] += g[c] / 6.0;
    }
  }
  for (std::size_t i = 0; i < gradient.size(); ++i) gradient[i] *= tables.constraint_mask[i / 3];
  // V(x + lambda G) = V(x) + c1 lambda + c2 lambda^2 + c3 lambda^3, per face a.(b x c) / 6.
  double c0 = 0.0, c1 = 0.0, c2 = 0.0, c3 = 0.0;
  for (const auto& t : tables.boundary_triangles) {
    const Vector a = at(x, t[0]), b = at(x, t[1]), c = at(x, t[2]);
    const Vector ga = at(gradient, t[0]), gb = at(gradient, t[1]), gc = at(gradient, t[2]);
    c0 += dot(a, cross(b, c));
    c1 += dot(ga, cross(b, c)) + dot(a, cross(gb, c)) + dot(a, cross(b, gc));
    c2 += dot(a, cross(gb, gc)) + dot(ga, cross(b, gc)) + dot(ga, cross(gb, c));
    c3 += dot(ga, cross(gb, gc));
  }
  const double residual_0 = c0 / 6.0 - tables.rest_volume_m3;
  c1 /= 6.0;
  c2 /= 6.0;
  c3 /= 6.0;
  double lambda = 0.0;  // Newton from 0 finds the root nearest zero: the smallest correction
  for (int k = 0; k < tables.options.volume_newton_iterations; ++k) {
    const double value = residual_0 + lambda * (c1 + lambda * (c2 + lambda * c3));
    const double slope = c1 + lambda * (2.0 * c2 + 3.0 * lambda * c3);
    if (slope != 0.0) lambda -= value / slope;
  }
  for (std::size_t i = 0; i < x.size(); ++i) x[i] += lambda * gradient[i];
  return lambda;
}

}  // namespace

void step(const MassSpringModel& model, MassSpringData& data, const TissueInputs& inputs) noexcept {
  const MassSpringTables& tables = model.tables();
  const detail::TetFemTables& fem = tables.supports.tables();
  if (!detail::inputs_are_valid(fem, inputs)) {
    data.health.raise(HealthFlag::bad_sample);
    return;
  }
  const double h = tables.options.step_s;
  std::copy(data.positions_m.begin(), data.positions_m.end(), data.backup_positions_m.begin());
  std::copy(data.velocities_m_s.begin(), data.velocities_m_s.end(), data.backup_velocities_m_s.begin());
  detail::move_kinematic_nodes(fem, inputs, h, data.positions_m, data.velocities_m_s);
  std::fill(data.forces_n.begin(), data.forces_n.end(), 0.0);
  detail::add_external_forces(fem, inputs, data.positions_m, data.forces_n, data.report);
  add_spring_forces(tables, data.positions_m, data.forces_n);
  detail::central_difference_update(fem, data.forces_n, h, tables.options.damping_per_s, data.positions_m,
                                    data.velocities_m_s);
  if (tables.options.keep_volume) {
    const double lambda = project_volume(tables, data.positions_m, data.volume_gradient);
    for (std::size_t i = 0; i < data.velocities_m_s.size(); ++i)
      data.velocities_m_s[i] += lambda * data.volume_gradient[i] / h;
  }
  if (h > tables.stable_step_s) data.health.raise(HealthFlag::unstable_step);
  data.report.inverted_elements = detail::count_inverted_elements(fem, data.positions_m);
  if (data.report.inverted_elements > 0) data.health.raise(HealthFlag::inverted_element);
  if (!all_finite(data.positions_m) || !all_finite(data.velocities_m_s)) {
    std::copy(data.backup_positions_m.begin(), data.backup_positions_m.end(), data.positions_m.begin());
    std::copy(data.backup_velocities_m_s.begin(), data.backup_velocities_m_s.end(), data.velocities_m_s.begin());
    data.health.raise(HealthFlag::non_finite_state);
    return;
  }
  data.volume_change_pct = 100.0 *
                           (enclosed_volume_m3(tables.boundary_triangles, data.positions_m) - tables.rest_volume_m3) /
                           tables.rest_volume_m3;
  ++data.steps;
}

}  // namespace nav
