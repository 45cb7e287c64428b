#include "nav/tissue/tissue_loads.hpp"

#include <cmath>

namespace nav::detail {
namespace {

bool finite(const Point3& p) { return std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]); }

/// Rotation matrix (row-major) of the normalised quaternion (w, x, y, z).
std::array<double, 9> rotation_matrix(const std::array<double, 4>& q_wxyz) {
  const double norm =
      std::sqrt(q_wxyz[0] * q_wxyz[0] + q_wxyz[1] * q_wxyz[1] + q_wxyz[2] * q_wxyz[2] + q_wxyz[3] * q_wxyz[3]);
  const double w = q_wxyz[0] / norm, x = q_wxyz[1] / norm, y = q_wxyz[2] / norm, z = q_wxyz[3] / norm;
  return {1 - 2 * (y * y + z * z), 2 * (x * y - w * z),     2 * (x * z + w * y),
          2 * (x * y + w * z),     1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
          2 * (x * z - w * y),     2 * (y * z + w * x),     1 - 2 * (x * x + y * y)};
}

void add_probe_forces(const TetFemTables& tables, const SphereProbe& probe, std::span<const double> x,
                      std::span<double> forces, TissueStepReport& report) {
  Point3 total_n{0.0, 0.0, 0.0};
  for (std::int32_t node : tables.probe_nodes) {
    const std::size_t i = 3 * static_cast<std::size_t>(node);
    const Point3 offset{x[i] - probe.centre_m[0], x[i + 1] - probe.centre_m[1], x[i + 2] - probe.centre_m[2]};
    const double distance_m = std::sqrt(offset[0] * offset[0] + offset[1] * offset[1] + offset[2] * offset[2]);
    const double depth_m = probe.radius_m - distance_m;
    if (!(depth_m > 0.0 && distance_m > 0.0)) continue;
    const double scale = tables.probe_stiffness_n_m * depth_m / distance_m;
    for (int c = 0; c < 3; ++c) {
      forces[i + c] += scale * offset[c];
      total_n[c] += scale * offset[c];
    }
    ++report.probe_contacts;
  }
  report.probe_force_n = std::sqrt(total_n[0] * total_n[0] + total_n[1] * total_n[1] + total_n[2] * total_n[2]);
}

}  // namespace

bool inputs_are_valid(const TetFemTables& tables, const TissueInputs& inputs) noexcept {
  if (inputs.point_forces.size() > tables.max_point_forces || !std::isfinite(inputs.load_scale)) return false;
  for (const PointForce& force : inputs.point_forces)
    if (force.node < 0 || force.node >= tables.node_count || !finite(force.force_n)) return false;
  const auto& q = inputs.spring_frame.rotation_wxyz;
  const double q_norm_squared = q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3];
  if (!(std::isfinite(q_norm_squared) && q_norm_squared > 0.0)) return false;
  if (!finite(inputs.traction_pa) || !finite(inputs.spring_frame.translation_m) ||
      !finite(inputs.prescribed_displacement_m))
    return false;
  const SphereProbe& probe = inputs.probe;
  return !probe.active || (finite(probe.centre_m) && std::isfinite(probe.radius_m) && probe.radius_m >= 0.0);
}

void move_kinematic_nodes(const TetFemTables& tables, const TissueInputs& inputs, double step_s, std::span<double> x,
                          std::span<double> v) noexcept {
  const double inverse_step = step_s > 0.0 ? 1.0 / step_s : 0.0;
  for (std::int32_t node : tables.fixed_nodes)
    for (int c = 0; c < 3; ++c) {
      const std::size_t i = 3 * static_cast<std::size_t>(node) + c;
      x[i] = tables.rest_m[i];
      v[i] = 0.0;
    }
  for (std::int32_t node : tables.prescribed_nodes)
    for (int c = 0; c < 3; ++c) {
      const std::size_t i = 3 * static_cast<std::size_t>(node) + c;
      const double target_m = tables.rest_m[i] + inputs.prescribed_displacement_m[c];
      v[i] = (target_m - x[i]) * inverse_step;
      x[i] = target_m;
    }
}

void add_external_forces(const TetFemTables& tables, const TissueInputs& inputs, std::span<const double> x,
                         std::span<double> forces, TissueStepReport& report) noexcept {
  const double s = inputs.load_scale;
  for (std::int64_t n = 0; n < tables.node_count; ++n)
    for (int c = 0; c < 3; ++c) forces[3 * n + c] += s * tables.mass_kg[n] * tables.gravity_m_s2[c];
  for (const PointForce& force : inputs.point_forces) {
    const auto node = static_cast<std::size_t>(force.node);
    const auto [first, last] = point_force_patch(tables, node);
    if (first == last)
      for (std::size_t c = 0; c < 3; ++c) forces[3 * node + c] += s * force.force_n[c];
    for (std::size_t k = first; k < last; ++k)
      for (std::size_t c = 0; c < 3; ++c)
        forces[3 * static_cast<std::size_t>(tables.patch_nodes[k]) + c] +=
            s * tables.patch_weights[k] * force.force_n[c];
  }
  for (std::size_t k = 0; k < tables.traction_nodes.size(); ++k)
    for (int c = 0; c < 3; ++c)
      forces[3 * static_cast<std::size_t>(tables.traction_nodes[k]) + c] +=
          s * tables.traction_area_m2[k] * inputs.traction_pa[c];
  if (!tables.spring_nodes.empty()) {
    const std::array<double, 9> r = rotation_matrix(inputs.spring_frame.rotation_wxyz);
    const Point3& t = inputs.spring_frame.translation_m;
    for (std::int32_t node : tables.spring_nodes) {
      const std::size_t i = 3 * static_cast<std::size_t>(node);
      for (int c = 0; c < 3; ++c) {
        const double anchor_m = r[3 * c] * tables.rest_m[i] + r[3 * c + 1] * tables.rest_m[i + 1] +
                                r[3 * c + 2] * tables.rest_m[i + 2] + t[c];
        forces[i + c] += tables.spring_stiffness_n_m * (anchor_m - x[i + c]);
      }
    }
  }
  report.probe_contacts = 0;
  report.probe_force_n = 0.0;
  if (inputs.probe.active && tables.probe_stiffness_n_m > 0.0)
    add_probe_forces(tables, inputs.probe, x, forces, report);
}

void add_spring_product(const TetFemTables& tables, std::span<const double> p, double scale,
                        std::span<double> out) noexcept {
  const double k = scale * tables.spring_stiffness_n_m;
  for (std::int32_t node : tables.spring_nodes)
    for (int c = 0; c < 3; ++c)
      out[3 * static_cast<std::size_t>(node) + c] += k * p[3 * static_cast<std::size_t>(node) + c];
}

void zero_constrained(const TetFemTables& tables, std::span<double> v) noexcept {
  for (std::int32_t node : tables.fixed_nodes)
    for (int c = 0; c < 3; ++c) v[3 * static_cast<std::size_t>(node) + c] = 0.0;
  for (std::int32_t node : tables.prescribed_nodes)
    for (int c = 0; c < 3; ++c) v[3 * static_cast<std::size_t>(node) + c] = 0.0;
}

}  // namespace nav::detail
