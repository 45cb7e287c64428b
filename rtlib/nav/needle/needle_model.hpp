#pragma once
// A flexible needle as corotational beams: the immutable NeedleModel (element stiffness,
// masses) built once from NeedleParameters, and the NeedleData (node frames, velocities,
// the block-tridiagonal system and its workspace) carved from one arena. The base node is
// driven kinematically by the tracked pose; step() is noexcept, allocation-free, of fixed
// cost and bitwise repeatable.
#include <array>
#include <cstdint>
#include <span>

#include "nav/core/arena.hpp"
#include "nav/core/error.hpp"
#include "nav/core/health.hpp"
#include "nav/needle/beam_element.hpp"
#include "nav/needle/block_tridiagonal.hpp"
#include "nav/needle/needle_parameters.hpp"

namespace nav {

/// A rigid pose world_from_base: the base position in metres and the unit quaternion
/// (w, x, y, z) of the base frame; the needle extends along the frame's +x axis.
struct NeedlePose {
  std::array<double, 3> position_m{};
  std::array<double, 4> rotation_wxyz{1.0, 0.0, 0.0, 0.0};
};

/// What drives one needle step: the tracked base pose and an optional tip wrench (world axes).
struct NeedleInputs {
  NeedlePose base;
  std::array<double, 3> tip_force_n{};
  std::array<double, 3> tip_moment_n_m{};
};

/// What the last needle step did.
struct NeedleStepReport {
  std::array<double, 3> base_force_n{};  ///< force the holder exerts on the needle's base (the needle pushes the holder
                                         ///< with its opposite)
  int rejected_poses = 0;                ///< poses refused since the data was made
  bool pose_rejected = false;            ///< the last step's pose was refused (state kept)
};

/// The immutable needle: parameters, section, element stiffness and lumped inertia.
struct NeedleModel {
  NeedleParameters parameters;
  NeedleSection section;
  int element_count = 0;
  double element_length_m = 0.0;
  BeamStiffness local_stiffness;
  std::array<double, 2> end_and_inner_mass_kg{};               ///< lumped mass of end and inner nodes
  std::array<double, 2> end_and_inner_rotary_inertia_kg_m2{};  ///< rho J l per node (isotropic)

  int node_count() const { return element_count + 1; }
  double node_mass_kg(int node) const;
  double node_rotary_inertia_kg_m2(int node) const;
};

/// State and workspace of one needle, carved from one arena at init.
struct NeedleData {
  Arena arena;
  std::span<double> positions_m;               ///< 3 per node
  std::span<double> rotations_wxyz;            ///< 4 per node, node frames (x along the shaft at rest)
  std::span<double> velocities_m_s;            ///< 3 per node
  std::span<double> angular_velocities_rad_s;  ///< 3 per node, world axes
  HealthFlags health;                          ///< raised by steps, cleared by the caller
  NeedleStepReport report;
  std::int64_t steps = 0;

  // Last good state, restored when a step fails.
  std::span<double> start_positions_m, start_rotations_wxyz, start_velocities_m_s, start_angular_velocities_rad_s;
  // Workspace (meaningless between steps, except the factor, kept for constraint solves).
  std::span<double> forces, residual;  ///< 6 per node
  BlockTridiagonal system;             ///< over the free nodes 1..n
  std::span<double> inverse_diagonal, inverse_column;
  /// A^-1's translational part over the free nodes, dense, row-major, translational_stride
  /// values per row (3 per free node, padded to whole lanes of the needle's kernels, which
  /// may read a row's padding and, from the last row, a lanes' width past it).
  std::span<double> translational_compliance;
  std::size_t translational_stride = 0;

  explicit NeedleData(Arena block) : arena(std::move(block)) {}
};

/// The position (3 values per node) of `node` in a node array, in metres.
inline Eigen::Vector3d node_position_m(std::span<const double> positions_m, int node) noexcept {
  return Eigen::Map<const Eigen::Vector3d>(positions_m.data() + 3 * static_cast<std::size_t>(node));
}

/// The frame (4 values per node, w x y z) of `node` in a node array.
inline Eigen::Quaterniond node_rotation(std::span<const double> rotations_wxyz, int node) noexcept {
  const double* q = rotations_wxyz.data() + 4 * static_cast<std::size_t>(node);
  return Eigen::Quaterniond(q[0], q[1], q[2], q[3]);
}

/// Builds the model; the Error names the parameter at fault.
Result<NeedleModel> make_needle_model(const NeedleParameters& parameters);

/// The data of `model`, straight and at rest at `base` (which must be finite and unit).
Result<NeedleData> make_needle_data(const NeedleModel& model, const NeedlePose& base);

/// Whether `base` has a finite position and a finite unit quaternion (within 1e-6 in norm²).
bool is_finite_unit_pose(const NeedlePose& base) noexcept;

/// Puts the needle of `data` straight and at rest at `base` (finite and unit), along its +x.
void place_straight_needle(const NeedleModel& model, NeedleData& data, const NeedlePose& base) noexcept;

}  // namespace nav
