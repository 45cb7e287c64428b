// Step-time integration of a FrameTissueModel: implicit Euler or quasi-static Newton steps
// with a banded Cholesky or block-Jacobi CG solve, and the diagnostics.
#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "nav/connective/banded_cholesky.hpp"
#include "nav/connective/frame_kernels.hpp"
#include "nav/connective/frame_tissue_model.hpp"
#include "nav/core/finite.hpp"

namespace nav {
namespace {

using detail::FrameTables;
using detail::FrameWorkspace;
using Matrix6 = Eigen::Matrix<double, 6, 6>;

FrameWorkspace workspace(FrameTissueData& data) {
  return {data.positions_m,    data.rotations, data.point_gradients,
          data.point_stresses, data.pair_arms, data.frame_spins};
}

bool inputs_are_valid(const FrameTables& t, const FrameTissueInputs& inputs) {
  bool valid = std::isfinite(inputs.load_scale) && inputs.frame_forces.size() <= t.max_frame_forces;
  valid =
      valid && (inputs.driven_positions_m.empty() || inputs.driven_positions_m.size() == 3 * t.driven_frames.size());
  for (double value : inputs.driven_positions_m) valid = valid && std::isfinite(value);
  valid = valid && (inputs.driven_orientations_wxyz.empty() ||
                    inputs.driven_orientations_wxyz.size() == 4 * t.driven_frames.size());
  for (std::size_t d = 0; d < inputs.driven_orientations_wxyz.size() / 4; ++d) {
    double norm2 = 0.0;
    for (int a = 0; a < 4; ++a)
      norm2 += inputs.driven_orientations_wxyz[4 * d + a] * inputs.driven_orientations_wxyz[4 * d + a];
    valid = valid && std::isfinite(norm2) && norm2 > 0.0;
  }
  for (const FrameForce& force : inputs.frame_forces) {
    valid = valid && force.frame >= 0 && force.frame < t.frame_count;
    for (int a = 0; a < 3; ++a) valid = valid && std::isfinite(force.force_n[a]) && std::isfinite(force.torque_n_m[a]);
  }
  return valid;
}

void zero_constrained(const FrameTables& t, std::span<double> v) {
  for (std::size_t k = 0; k < v.size(); ++k)
    if (t.constrained[k] != 0) v[k] = 0.0;
}

/// Puts the driven translations at their targets with the velocity that took them there.
void move_driven_frames(const FrameTables& t, const FrameTissueInputs& inputs, FrameTissueData& data) {
  const double h = t.options.step_s;
  for (std::size_t d = 0; d < t.driven_frames.size(); ++d) {
    const auto f = static_cast<std::size_t>(t.driven_frames[d]);
    for (std::size_t a = 0; a < 3; ++a) {
      if (!t.driven_axes[d][a]) continue;
      const double target =
          inputs.driven_positions_m.empty() ? t.rest_m[3 * f + a] : inputs.driven_positions_m[3 * d + a];
      data.velocities[6 * f + a] = (target - data.positions_m[3 * f + a]) / h;
      data.positions_m[3 * f + a] = target;
    }
    if (!t.hold_driven_rotations) continue;
    const std::span<const double> q = inputs.driven_orientations_wxyz;
    const Eigen::Quaterniond target =
        q.empty() ? Eigen::Quaterniond::Identity()
                  : Eigen::Quaterniond(q[4 * d], q[4 * d + 1], q[4 * d + 2], q[4 * d + 3]).normalized();
    const Eigen::AngleAxisd turn(
        target * Eigen::Quaterniond(data.orientations_wxyz[4 * f], data.orientations_wxyz[4 * f + 1],
                                    data.orientations_wxyz[4 * f + 2], data.orientations_wxyz[4 * f + 3])
                     .conjugate());
    for (std::size_t a = 0; a < 3; ++a)
      data.velocities[6 * f + 3 + a] = turn.angle() * turn.axis()[static_cast<int>(a)] / h;
    data.orientations_wxyz[4 * f] = target.w();
    data.orientations_wxyz[4 * f + 1] = target.x();
    data.orientations_wxyz[4 * f + 2] = target.y();
    data.orientations_wxyz[4 * f + 3] = target.z();
  }
}

/// Forces at the current frames: elastic, gravity and frame forces.
void compute_forces(const FrameTables& t, FrameTissueData& data, const FrameTissueInputs& inputs) {
  detail::update_rotations(t, data.orientations_wxyz, data.rotations, data.inertias);
  std::fill(data.forces.begin(), data.forces.end(), 0.0);
  const FrameWorkspace work = workspace(data);
  data.report.inverted_points = detail::add_elastic_forces(t, work, data.forces);
  detail::add_gravity(t, work, inputs.load_scale, data.forces);
  for (const FrameForce& force : inputs.frame_forces)
    for (int a = 0; a < 3; ++a) {
      data.forces[6 * static_cast<std::size_t>(force.frame) + a] += inputs.load_scale * force.force_n[a];
      data.forces[6 * static_cast<std::size_t>(force.frame) + 3 + a] += inputs.load_scale * force.torque_n_m[a];
    }
}

/// Identity rows and columns for the constrained DOFs of the band.
void constrain_band(const FrameTables& t, std::span<double> band) {
  const auto b = static_cast<std::size_t>(t.half_bandwidth);
  const std::size_t n = t.constrained.size();
  for (std::size_t k = 0; k < n; ++k) {
    if (t.constrained[k] == 0) continue;
    for (std::size_t i = k; i <= std::min(n - 1, k + b); ++i) band[k * (b + 1) + (i - k)] = i == k ? 1.0 : 0.0;
    for (std::size_t j = k > b ? k - b : 0; j < k; ++j) band[j * (b + 1) + (k - j)] = 0.0;
  }
}

/// Inverts the 6x6 frame blocks in place (identity rows for constrained DOFs).
void invert_blocks(const FrameTables& t, std::span<double> blocks) {
  for (std::size_t i = 0; i < static_cast<std::size_t>(t.frame_count); ++i) {
    Eigen::Map<Matrix6> block(blocks.data() + 36 * i);
    for (int a = 0; a < 6; ++a)
      if (t.constrained[6 * i + static_cast<std::size_t>(a)] != 0) {
        block.row(a).setZero();
        block.col(a).setZero();
        block(a, a) = 1.0;
      }
    const Eigen::LLT<Matrix6> llt(block);
    if (llt.info() == Eigen::Success) {
      block = llt.solve(Matrix6::Identity());
    } else {
      const Eigen::Matrix<double, 6, 1> diagonal = block.diagonal().cwiseMax(1e-300);
      block = diagonal.cwiseInverse().asDiagonal();
    }
  }
}

/// data.product = A p with A = mass_scale M + stiffness_scale K, constrained DOFs as identity.
void system_product(const FrameTables& t, FrameTissueData& data, std::span<const double> p, double mass_scale,
                    double stiffness_scale) {
  std::fill(data.product.begin(), data.product.end(), 0.0);
  detail::add_mass_product(t, data.inertias, p, mass_scale, data.product);
  detail::add_stiffness_product(t, workspace(data), p, stiffness_scale, data.product);
  for (std::size_t k = 0; k < p.size(); ++k)
    if (t.constrained[k] != 0) data.product[k] = p[k];
}

void apply_blocks(const FrameTables& t, std::span<const double> blocks, std::span<const double> in,
                  std::span<double> out) {
  for (std::size_t i = 0; i < static_cast<std::size_t>(t.frame_count); ++i)
    Eigen::Map<Eigen::Matrix<double, 6, 1>>(out.data() + 6 * i).noalias() =
        Eigen::Map<const Matrix6>(blocks.data() + 36 * i) *
        Eigen::Map<const Eigen::Matrix<double, 6, 1>>(in.data() + 6 * i);
}

double dot(std::span<const double> a, std::span<const double> b) {
  double sum = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k) sum += a[k] * b[k];
  return sum;
}

/// Preconditioned CG from zero, cg_iterations iterations (fewer only when the residual
/// vanishes), on data.rhs into data.solution.
void solve_cg(const FrameTables& t, FrameTissueData& data, double mass_scale, double stiffness_scale) {
  detail::assemble(t, workspace(data), data.inertias, mass_scale, stiffness_scale, data.blocks, {});
  invert_blocks(t, data.blocks);
  std::fill(data.solution.begin(), data.solution.end(), 0.0);
  std::copy(data.rhs.begin(), data.rhs.end(), data.residual.begin());
  apply_blocks(t, data.blocks, data.residual, data.preconditioned);
  std::copy(data.preconditioned.begin(), data.preconditioned.end(), data.direction.begin());
  const double rhs_norm = std::sqrt(dot(data.rhs, data.rhs));
  double rz = dot(data.residual, data.preconditioned);
  int iterations = 0;
  for (; iterations < t.options.cg_iterations && rz > 0.0; ++iterations) {
    system_product(t, data, data.direction, mass_scale, stiffness_scale);
    const double curvature = dot(data.direction, data.product);
    if (!(curvature > 0.0)) break;
    const double alpha = rz / curvature;
    for (std::size_t k = 0; k < data.solution.size(); ++k) {
      data.solution[k] += alpha * data.direction[k];
      data.residual[k] -= alpha * data.product[k];
    }
    apply_blocks(t, data.blocks, data.residual, data.preconditioned);
    const double next = dot(data.residual, data.preconditioned);
    const double beta = next / rz;
    rz = next;
    for (std::size_t k = 0; k < data.direction.size(); ++k)
      data.direction[k] = data.preconditioned[k] + beta * data.direction[k];
  }
  data.report.solver_iterations = iterations;
  data.report.solver_relative_residual = rhs_norm > 0.0 ? std::sqrt(dot(data.residual, data.residual)) / rhs_norm : 0.0;
}

void solve_banded(const FrameTables& t, FrameTissueData& data, double mass_scale, double stiffness_scale) {
  detail::assemble(t, workspace(data), data.inertias, mass_scale, stiffness_scale, data.blocks, data.band);
  constrain_band(t, data.band);
  std::copy(data.rhs.begin(), data.rhs.end(), data.solution.begin());
  const auto n = data.rhs.size(), b = static_cast<std::size_t>(t.half_bandwidth);
  data.report.solver_iterations = 1;
  if (!banded_cholesky_factor(data.band, n, b)) {
    std::fill(data.solution.begin(), data.solution.end(), 0.0);
    data.report.solver_relative_residual = 1.0;
    return;
  }
  banded_cholesky_solve(data.band, n, b, data.solution);
  system_product(t, data, data.solution, mass_scale, stiffness_scale);
  double error = 0.0;
  for (std::size_t k = 0; k < n; ++k) error += (data.product[k] - data.rhs[k]) * (data.product[k] - data.rhs[k]);
  const double rhs_norm = std::sqrt(dot(data.rhs, data.rhs));
  data.report.solver_relative_residual = rhs_norm > 0.0 ? std::sqrt(error) / rhs_norm : 0.0;
}

void solve(const FrameTables& t, FrameTissueData& data, double mass_scale, double stiffness_scale) {
  zero_constrained(t, data.rhs);
  if (t.options.solver == FrameSolver::banded_cholesky)
    solve_banded(t, data, mass_scale, stiffness_scale);
  else
    solve_cg(t, data, mass_scale, stiffness_scale);
  zero_constrained(t, data.solution);
  if (data.report.solver_relative_residual > t.options.cg_residual_bound)
    data.health.raise(HealthFlag::solver_not_converged);
}

/// Moves every frame by `scale` times the 6-vector `motion` (its free DOFs): translation, then
/// the rotation increment exp([scale dr]x) applied on the left of the orientation.
void move_frames(const FrameTables& t, FrameTissueData& data, std::span<const double> motion, double scale) {
  for (std::size_t i = 0; i < static_cast<std::size_t>(t.frame_count); ++i) {
    for (std::size_t a = 0; a < 3; ++a)
      if (t.constrained[6 * i + a] == 0) data.positions_m[3 * i + a] += scale * motion[6 * i + a];
    Eigen::Vector3d turn;
    for (std::size_t a = 0; a < 3; ++a)
      turn[static_cast<int>(a)] = t.constrained[6 * i + 3 + a] != 0 ? 0.0 : scale * motion[6 * i + 3 + a];
    const double angle = turn.norm();
    if (!(angle > 0.0)) continue;
    const Eigen::Quaterniond dq(Eigen::AngleAxisd(angle, turn / angle));
    Eigen::Quaterniond q(data.orientations_wxyz[4 * i], data.orientations_wxyz[4 * i + 1],
                         data.orientations_wxyz[4 * i + 2], data.orientations_wxyz[4 * i + 3]);
    q = (dq * q).normalized();
    data.orientations_wxyz[4 * i] = q.w();
    data.orientations_wxyz[4 * i + 1] = q.x();
    data.orientations_wxyz[4 * i + 2] = q.y();
    data.orientations_wxyz[4 * i + 3] = q.z();
  }
}

/// (1 + h a) M dv + (h^2 + h b) K dv = h (f - a M v) - (h^2 + h b) K v_free; v += dv; q += h v.
void implicit_euler(const FrameTables& t, FrameTissueData& data) {
  const FrameTissueOptions& o = t.options;
  const double h = o.step_s, stiffness_scale = h * h + h * o.rayleigh_stiffness_s;
  std::copy(data.velocities.begin(), data.velocities.end(), data.free_velocities.begin());
  zero_constrained(t, data.free_velocities);
  for (std::size_t k = 0; k < data.rhs.size(); ++k) data.rhs[k] = h * data.forces[k];
  detail::add_mass_product(t, data.inertias, data.velocities, -h * o.rayleigh_mass_per_s, data.rhs);
  detail::add_stiffness_product(t, workspace(data), data.free_velocities, -stiffness_scale, data.rhs);
  solve(t, data, 1.0 + h * o.rayleigh_mass_per_s, stiffness_scale);
  for (std::size_t k = 0; k < data.velocities.size(); ++k)
    if (t.constrained[k] == 0) data.velocities[k] += data.solution[k];
  move_frames(t, data, data.velocities, h);
}

/// ((1 + b/h) K + a/h M) dq = f; q += dq; v = dq / h.
void quasi_static(const FrameTables& t, FrameTissueData& data) {
  const FrameTissueOptions& o = t.options;
  const double h = o.step_s;
  std::copy(data.forces.begin(), data.forces.end(), data.rhs.begin());
  solve(t, data, o.rayleigh_mass_per_s / h, 1.0 + o.rayleigh_stiffness_s / h);
  move_frames(t, data, data.solution, 1.0);
  for (std::size_t k = 0; k < data.velocities.size(); ++k)
    if (t.constrained[k] == 0) data.velocities[k] = data.solution[k] / h;
}

void restore(FrameTissueData& data, std::size_t n) {
  std::copy(data.backup.begin(), data.backup.begin() + 3 * n, data.positions_m.begin());
  std::copy(data.backup.begin() + 3 * n, data.backup.begin() + 7 * n, data.orientations_wxyz.begin());
  std::copy(data.backup.begin() + 7 * n, data.backup.begin() + 13 * n, data.velocities.begin());
}

}  // namespace

void step(const FrameTissueModel& model, FrameTissueData& data, const FrameTissueInputs& inputs) noexcept {
  const FrameTables& t = model.tables();
  if (!inputs_are_valid(t, inputs)) {
    data.health.raise(HealthFlag::bad_sample);
    return;
  }
  const std::size_t n = static_cast<std::size_t>(t.frame_count);
  std::copy(data.positions_m.begin(), data.positions_m.end(), data.backup.begin());
  std::copy(data.orientations_wxyz.begin(), data.orientations_wxyz.end(), data.backup.begin() + 3 * n);
  std::copy(data.velocities.begin(), data.velocities.end(), data.backup.begin() + 7 * n);
  move_driven_frames(t, inputs, data);
  compute_forces(t, data, inputs);
  if (data.report.inverted_points > 0) data.health.raise(HealthFlag::inverted_element);
  if (t.options.integrator == FrameIntegrator::implicit_euler)
    implicit_euler(t, data);
  else
    quasi_static(t, data);
  if (data.report.solver_relative_residual > t.options.cg_residual_bound) {
    // An unsolved system (a layout too ill-conditioned for the iterations given) would be
    // integrated into a motion of any size: the step is not taken.
    restore(data, n);
    return;
  }
  compute_forces(t, data, inputs);
  for (std::size_t d = 0; d < t.driven_frames.size(); ++d)
    for (std::size_t a = 0; a < 3; ++a)
      data.driven_forces_n[3 * d + a] = data.forces[6 * static_cast<std::size_t>(t.driven_frames[d]) + a];
  if (!all_finite(data.positions_m) || !all_finite(data.orientations_wxyz) || !all_finite(data.velocities) ||
      !all_finite(data.driven_forces_n)) {
    restore(data, n);
    std::fill(data.driven_forces_n.begin(), data.driven_forces_n.end(), 0.0);
    data.health.raise(HealthFlag::non_finite_state);
    return;
  }
  ++data.steps;
}

double elastic_energy_j(const FrameTissueModel& model, const FrameTissueData& data) noexcept {
  return detail::elastic_energy(model.tables(), data.positions_m, data.orientations_wxyz);
}

void elastic_forces(const FrameTissueModel& model, FrameTissueData& data, std::span<double> forces) noexcept {
  const FrameTables& t = model.tables();
  detail::update_rotations(t, data.orientations_wxyz, data.rotations, data.inertias);
  std::fill(forces.begin(), forces.end(), 0.0);
  detail::add_elastic_forces(t, workspace(data), forces);
}

void stiffness_product(const FrameTissueModel& model, FrameTissueData& data, std::span<const double> dq,
                       std::span<double> out) noexcept {
  std::fill(out.begin(), out.end(), 0.0);
  detail::add_stiffness_product(model.tables(), workspace(data), dq, 1.0, out);
}

Point3 material_point_m(const FrameTissueModel& model, const FrameTissueData& data, const PointNeighbours& neighbours,
                        const Point3& rest_m) noexcept {
  const FrameTables& t = model.tables();
  Eigen::Vector3d p = Eigen::Vector3d::Zero();
  for (std::size_t k = 0; k < neighbours.frames.size(); ++k) {
    const auto i = static_cast<std::size_t>(neighbours.frames[k]);
    const Eigen::Quaterniond q(data.orientations_wxyz[4 * i], data.orientations_wxyz[4 * i + 1],
                               data.orientations_wxyz[4 * i + 2], data.orientations_wxyz[4 * i + 3]);
    const Eigen::Vector3d arm(rest_m[0] - t.rest_m[3 * i], rest_m[1] - t.rest_m[3 * i + 1],
                              rest_m[2] - t.rest_m[3 * i + 2]);
    p += neighbours.weights[k] *
         (Eigen::Vector3d(data.positions_m[3 * i], data.positions_m[3 * i + 1], data.positions_m[3 * i + 2]) + q * arm);
  }
  return {p.x(), p.y(), p.z()};
}

}  // namespace nav
