#include "nav/needle/needle_step.hpp"

#include <algorithm>
#include <cmath>

#include "nav/core/finite.hpp"
#include "nav/needle/rotation_vector.hpp"

namespace nav {

namespace {

using Vec3Map = Eigen::Map<Eigen::Vector3d>;
using ConstVec3Map = Eigen::Map<const Eigen::Vector3d>;

void set_node_rotation(std::span<double> rotations, int node, const Eigen::Quaterniond& q) {
  double* out = rotations.data() + 4 * static_cast<std::size_t>(node);
  out[0] = q.w();
  out[1] = q.x();
  out[2] = q.y();
  out[3] = q.z();
}

Eigen::Quaterniond pose_rotation(const NeedlePose& pose) {
  return Eigen::Quaterniond(pose.rotation_wxyz[0], pose.rotation_wxyz[1], pose.rotation_wxyz[2], pose.rotation_wxyz[3])
      .normalized();
}

/// Mass-matrix coefficients (a, b): inertial force = m (a dx - b v_start).
std::array<double, 2> inertia_coefficients(const NeedleParameters& p) {
  if (p.integrator == NeedleIntegrator::quasi_static) return {0.0, 0.0};
  return {1.0 / (p.step_s * p.step_s) + p.rayleigh_mass_per_s / p.step_s, 1.0 / p.step_s};
}

/// Assembles internal forces (into data.forces), the residual and the system for the free
/// nodes, from the current iterate.
void assemble(const NeedleModel& model, NeedleData& data, const NeedleInputs& inputs) {
  const int n = model.node_count();
  const auto [a, b] = inertia_coefficients(model.parameters);
  std::fill(data.forces.begin(), data.forces.end(), 0.0);
  std::fill(data.system.diagonal.begin(), data.system.diagonal.end(), 0.0);
  std::fill(data.system.upper.begin(), data.system.upper.end(), 0.0);
  for (int e = 0; e < model.element_count; ++e) {
    const BeamEnds ends{node_position_m(data.positions_m, e), node_position_m(data.positions_m, e + 1),
                        node_rotation(data.rotations_wxyz, e), node_rotation(data.rotations_wxyz, e + 1)};
    const BeamResponse response = corotational_beam_response(model.local_stiffness, model.element_length_m, ends);
    Eigen::Map<Vector12d>(data.forces.data() + 6 * static_cast<std::size_t>(e)) += response.forces;
    // Free node k has block row k - 1.
    if (e >= 1)
      Eigen::Map<Matrix6d>(data.system.diagonal.data() + 36 * static_cast<std::size_t>(e - 1)) += response.tangent_aa;
    Eigen::Map<Matrix6d>(data.system.diagonal.data() + 36 * static_cast<std::size_t>(e)) += response.tangent_bb;
    if (e >= 1)
      Eigen::Map<Matrix6d>(data.system.upper.data() + 36 * static_cast<std::size_t>(e - 1)) += response.tangent_ab;
  }
  for (int node = 1; node < n; ++node) {
    const std::size_t i = static_cast<std::size_t>(node);
    const Eigen::Vector3d dx = node_position_m(data.positions_m, node) - node_position_m(data.start_positions_m, node);
    const Eigen::Vector3d dtheta = rotation_vector_from_quaternion(
        node_rotation(data.rotations_wxyz, node) * node_rotation(data.start_rotations_wxyz, node).conjugate());
    const double m = model.node_mass_kg(node), j = model.node_rotary_inertia_kg_m2(node);
    Eigen::Map<Vector6d> r(data.residual.data() + 6 * i);
    r.head<3>() = -ConstVec3Map(data.forces.data() + 6 * i) -
                  m * (a * dx - b * ConstVec3Map(data.start_velocities_m_s.data() + 3 * i));
    r.tail<3>() = -ConstVec3Map(data.forces.data() + 6 * i + 3) -
                  j * (a * dtheta - b * ConstVec3Map(data.start_angular_velocities_rad_s.data() + 3 * i));
    if (node == n - 1) {
      r.head<3>() += ConstVec3Map(inputs.tip_force_n.data());
      r.tail<3>() += ConstVec3Map(inputs.tip_moment_n_m.data());
    }
    Eigen::Map<Matrix6d> block(data.system.diagonal.data() + 36 * (i - 1));
    for (int d = 0; d < 3; ++d) {
      block(d, d) += a * m;
      block(3 + d, 3 + d) += a * j;
    }
  }
}

/// Moves the free nodes by `delta` (6 per node, node 0 unused).
void move_free_nodes(const NeedleModel& model, NeedleData& data, std::span<const double> delta) {
  for (int node = 1; node < model.node_count(); ++node) {
    const std::size_t i = static_cast<std::size_t>(node);
    Vec3Map(data.positions_m.data() + 3 * i) += ConstVec3Map(delta.data() + 6 * i);
    const Eigen::Quaterniond turned = quaternion_from_rotation_vector(ConstVec3Map(delta.data() + 6 * i + 3)) *
                                      node_rotation(data.rotations_wxyz, node);
    set_node_rotation(data.rotations_wxyz, node, turned.normalized());
  }
}

/// Velocities from the motion since the step started (backward Euler).
void update_velocities(const NeedleModel& model, NeedleData& data) {
  const double h = model.parameters.step_s;
  for (int node = 0; node < model.node_count(); ++node) {
    const std::size_t i = static_cast<std::size_t>(node);
    Vec3Map(data.velocities_m_s.data() + 3 * i) =
        (node_position_m(data.positions_m, node) - node_position_m(data.start_positions_m, node)) / h;
    Vec3Map(data.angular_velocities_rad_s.data() + 3 * i) =
        rotation_vector_from_quaternion(node_rotation(data.rotations_wxyz, node) *
                                        node_rotation(data.start_rotations_wxyz, node).conjugate()) /
        h;
  }
}

void restore_start(NeedleData& data) {
  std::copy(data.start_positions_m.begin(), data.start_positions_m.end(), data.positions_m.begin());
  std::copy(data.start_rotations_wxyz.begin(), data.start_rotations_wxyz.end(), data.rotations_wxyz.begin());
  std::copy(data.start_velocities_m_s.begin(), data.start_velocities_m_s.end(), data.velocities_m_s.begin());
  std::copy(data.start_angular_velocities_rad_s.begin(), data.start_angular_velocities_rad_s.end(),
            data.angular_velocities_rad_s.begin());
}

}  // namespace

bool accept_base_pose(const NeedleModel& model, NeedleData& data, const NeedlePose& base) noexcept {
  data.report.pose_rejected = true;
  double norm2 = 0.0;
  for (double v : base.rotation_wxyz) norm2 += v * v;
  bool ok = std::isfinite(norm2) && std::abs(std::sqrt(norm2) - 1.0) <= 1e-3;
  for (double v : base.position_m) ok = ok && std::isfinite(v);
  if (ok) {
    // The farthest any needle point moves under the rigid base increment: |dp| + L * angle.
    const Eigen::Quaterniond turn = pose_rotation(base) * node_rotation(data.rotations_wxyz, 0).conjugate();
    const double jump_m = (ConstVec3Map(base.position_m.data()) - node_position_m(data.positions_m, 0)).norm() +
                          model.parameters.length_m * rotation_vector_from_quaternion(turn).norm();
    ok = jump_m <= model.parameters.max_pose_jump_m;
  }
  if (!ok) {
    data.health.raise(HealthFlag::bad_sample);
    ++data.report.rejected_poses;
    return false;
  }
  data.report.pose_rejected = false;
  return true;
}

bool needle_free_motion(const NeedleModel& model, NeedleData& data, const NeedleInputs& inputs) noexcept {
  std::copy(data.positions_m.begin(), data.positions_m.end(), data.start_positions_m.begin());
  std::copy(data.rotations_wxyz.begin(), data.rotations_wxyz.end(), data.start_rotations_wxyz.begin());
  std::copy(data.velocities_m_s.begin(), data.velocities_m_s.end(), data.start_velocities_m_s.begin());
  std::copy(data.angular_velocities_rad_s.begin(), data.angular_velocities_rad_s.end(),
            data.start_angular_velocities_rad_s.begin());
  // Carry the whole needle rigidly with the base increment: the first Newton iterate.
  const Eigen::Quaterniond base_rotation = pose_rotation(inputs.base);
  const Eigen::Quaterniond turn = base_rotation * node_rotation(data.rotations_wxyz, 0).conjugate();
  const Eigen::Vector3d old_base = node_position_m(data.positions_m, 0),
                        new_base = ConstVec3Map(inputs.base.position_m.data());
  for (int node = 0; node < model.node_count(); ++node) {
    Vec3Map p(data.positions_m.data() + 3 * static_cast<std::size_t>(node));
    p = new_base + turn * (Eigen::Vector3d(p) - old_base);
    set_node_rotation(data.rotations_wxyz, node, (turn * node_rotation(data.rotations_wxyz, node)).normalized());
  }
  set_node_rotation(data.rotations_wxyz, 0, base_rotation);
  for (int iteration = 0; iteration < model.parameters.newton_iterations; ++iteration) {
    assemble(model, data, inputs);
    if (!factor_block_tridiagonal(data.system)) {
      restore_start(data);
      data.health.raise(HealthFlag::non_finite_state);
      return false;
    }
    solve_block_tridiagonal(data.system, data.residual.subspan(6));
    move_free_nodes(model, data, data.residual);
  }
  for (int c = 0; c < 3; ++c) data.report.base_force_n[c] = data.forces[static_cast<std::size_t>(c)];
  if (!all_finite(data.positions_m) || !all_finite(data.rotations_wxyz)) {
    restore_start(data);
    data.health.raise(HealthFlag::non_finite_state);
    return false;
  }
  return true;
}

void apply_needle_correction(const NeedleModel& model, NeedleData& data, std::span<double> nodal_forces) noexcept {
  solve_block_tridiagonal(data.system, nodal_forces.subspan(6));
  move_free_nodes(model, data, nodal_forces);
  update_velocities(model, data);
}

void update_needle_compliance(NeedleData& data, int first_node) noexcept {
  translational_inverse_blocks(data.system, std::max(first_node, 1) - 1, data.inverse_diagonal, data.inverse_column,
                               data.translational_compliance, data.translational_stride);
}

void step(const NeedleModel& model, NeedleData& data, const NeedleInputs& inputs) noexcept {
  if (!accept_base_pose(model, data, inputs.base)) return;
  if (!needle_free_motion(model, data, inputs)) return;
  update_velocities(model, data);
  ++data.steps;
}

Eigen::Vector3d needle_tip_m(const NeedleData& data) noexcept {
  return node_position_m(data.positions_m, data.system.blocks);
}

Eigen::Vector3d needle_tip_direction(const NeedleData& data) noexcept {
  return node_rotation(data.rotations_wxyz, data.system.blocks) * Eigen::Vector3d::UnitX();
}

}  // namespace nav
