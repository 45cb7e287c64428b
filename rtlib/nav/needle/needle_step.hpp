#pragma once
// The needle's step and its pieces, which the needle-tissue solver calls in between: accept
// the tracked base pose, the free motion (fixed Newton iterations on the block-tridiagonal
// system), and the correction by constraint forces through the same factor.
#include <span>

#include "nav/needle/needle_model.hpp"

namespace nav {

/// Checks the pose (finite, unit quaternion within 1e-3, no point of the needle moved more
/// than max_pose_jump_m from the last accepted pose). A bad pose raises bad_sample, counts
/// in report.rejected_poses and leaves the state untouched; returns whether it was accepted.
bool accept_base_pose(const NeedleModel& model, NeedleData& data, const NeedlePose& base) noexcept;

/// Saves the state, moves the needle rigidly with the base increment, then runs the fixed
/// Newton iterations of the step under the inputs' tip wrench. Leaves the factored system
/// (A = M/h^2 + K, or K quasi-static) in data.system for compliance and correction, and the
/// velocities to the correction (or step()), which moves the nodes last. Call
/// only after accept_base_pose() returned true. False (state restored, non_finite_state
/// raised) when the system or the state is not usable.
bool needle_free_motion(const NeedleModel& model, NeedleData& data, const NeedleInputs& inputs) noexcept;

/// Moves the free nodes by A^-1 f for nodal forces f (6 per node: force then moment, world
/// axes; node 0's entries ignored) and updates the velocities accordingly.
void apply_needle_correction(const NeedleModel& model, NeedleData& data, std::span<double> nodal_forces) noexcept;

/// Fills data.translational_compliance with the blocks of A^-1 between the free nodes
/// first_node .. n (node indices, first_node >= 1).
void update_needle_compliance(NeedleData& data, int first_node) noexcept;

/// Where the translational compliance's rows of node `node` (>= 1) start, at its own column.
inline const double* needle_compliance_row(const NeedleData& data, int node) noexcept {
  const auto free = static_cast<std::size_t>(node - 1);
  return data.translational_compliance.data() + 3 * free * data.translational_stride + 3 * free;
}

/// The 3x3 translational compliance block between nodes i and j (both >= 1).
inline Eigen::Matrix3d needle_compliance_block(const NeedleData& data, int node_i, int node_j) noexcept {
  const std::size_t stride = data.translational_stride;
  return Eigen::Map<const Eigen::Matrix<double, 3, 3, Eigen::RowMajor>, 0, Eigen::OuterStride<>>(
      data.translational_compliance.data() + 3 * static_cast<std::size_t>(node_i - 1) * stride +
          3 * static_cast<std::size_t>(node_j - 1),
      Eigen::OuterStride<>(static_cast<Eigen::Index>(stride)));
}

/// One needle step without tissue: pose check, free motion, finite check.
void step(const NeedleModel& model, NeedleData& data, const NeedleInputs& inputs) noexcept;

/// Tip position and unit shaft direction at the tip (the tip node frame's x axis).
Eigen::Vector3d needle_tip_m(const NeedleData& data) noexcept;
Eigen::Vector3d needle_tip_direction(const NeedleData& data) noexcept;

}  // namespace nav
