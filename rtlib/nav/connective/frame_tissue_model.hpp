#pragma once
// Bosman, Duriez and Cotin's meshless frame-based connective tissue (digest 002): 6-DOF frames
// (position and rotation) carry integration points through shape functions; the deformation
// gradient of each point follows from the frames' motion (eq. 8), the St Venant-Kirchhoff
// law (eq. 18) gives the forces on the frames (eq. 17), and implicit Euler with the material
// tangent (eqs. 23-25) and a fixed number of CG iterations, or a banded Cholesky where the
// system is small, advances them. Model/Data: the model is built once and immutable; the
// data is one arena; step() is noexcept, allocation-free, fixed-cost and bitwise repeatable.
//
// Frame DOFs are 6 per frame: the translation and a rotation increment dr applied on the
// left, R <- exp([dr]x) R (world axes). Rest orientations are the identity.
#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "nav/connective/frame_layout.hpp"
#include "nav/core/arena.hpp"
#include "nav/core/error.hpp"
#include "nav/core/health.hpp"
#include "nav/tissue/elastic_material.hpp"

namespace nav {

namespace detail {
struct FrameTables;
}

/// Frames held by the tissue's surroundings.
struct FrameSupports {
  /// Frames held at rest in translation and rotation (a ligament's insertion on the wall).
  std::vector<std::int32_t> fixed_frames;
  /// Frames whose translation follows FrameTissueInputs::driven_positions_m, rotation free:
  /// attachments to an organ, or a face pulled in a traction test.
  std::vector<std::int32_t> driven_frames;
  /// Which translation axes of each driven frame are driven (empty: all three); the others
  /// are free.
  std::vector<std::array<bool, 3>> driven_axes;
  /// Holds the driven frames' rotations (at rest, or at FrameTissueInputs::driven_orientations_wxyz).
  /// A face pulled by its frames' positions alone is not held flat: its frames turn and let
  /// the material between them move.
  bool hold_driven_rotations = false;
};

/// The time integration of a step.
enum class FrameIntegrator {
  implicit_euler,  ///< backward Euler, one linearisation per step
  quasi_static,    ///< one Newton step towards equilibrium per call (Rayleigh terms relax it)
};

/// How the step's linear system is solved.
enum class FrameSolver {
  banded_cholesky,  ///< assembled in the band of the frame numbering and factored: exact, for small tissues
  cg_block_jacobi,  ///< matrix-free conjugate gradients, cg_iterations of them, 6x6 frame blocks as preconditioner
};

/// Numerical settings of a frame-based tissue.
struct FrameTissueOptions {
  FrameIntegrator integrator = FrameIntegrator::implicit_euler;
  FrameSolver solver = FrameSolver::cg_block_jacobi;
  double step_s = 0.01;
  int cg_iterations = 60;  ///< the paper's benchmark setting
  /// A solve that ends above this relative residual raises solver_not_converged and the step
  /// is not taken (the state stays as it was).
  double cg_residual_bound = 1e-2;
  /// Adds the geometric stiffness to the paper's material tangent M^T C M (off is the paper's
  /// choice): dF S+ (S+: the positive part of the stress) and the positive part of each
  /// frame's P : d2F/dr2. Without the latter, rotation fields that strain no point at first
  /// order have no stiffness: quasi-static steps then need rayleigh_mass_per_s > 0.
  bool geometric_stiffness = true;
  /// Rayleigh damping C = a M + b K.
  double rayleigh_mass_per_s = 0.0;
  double rayleigh_stiffness_s = 0.0;
  /// Systems whose band holds more entries than this are refused for banded_cholesky.
  std::int64_t max_band_entries = 4'000'000;
};

/// Everything a frame-based tissue is built from.
struct FrameTissueScene {
  FrameLayout layout;
  ElasticMaterial material;
  Point3 gravity_m_s2{0.0, 0.0, -9.81};
  FrameSupports supports;
  /// Most frame forces one step accepts.
  std::size_t max_frame_forces = 16;
};

/// A force and torque on one frame.
struct FrameForce {
  std::int32_t frame = 0;
  Point3 force_n{};
  Point3 torque_n_m{};
};

/// What drives one step. A step with a non-finite value, a driven-position count that is
/// neither 0 nor 3 per driven frame (orientations: 0 or 4), a zero quaternion, an out-of-range
/// frame or too many forces is refused with the state untouched (bad_sample).
struct FrameTissueInputs {
  /// Factor on gravity and frame forces, for a load ramp.
  double load_scale = 1.0;
  /// Positions of the driven frames (3 each, in FrameSupports order); empty: at rest.
  std::span<const double> driven_positions_m;
  /// Unit quaternions (w, x, y, z) of the driven frames when their rotations are held; empty:
  /// at rest.
  std::span<const double> driven_orientations_wxyz;
  std::span<const FrameForce> frame_forces;
};

/// What the last step did.
struct FrameStepReport {
  double solver_relative_residual = 0.0;
  int solver_iterations = 0;
  int inverted_points = 0;  ///< integration points with det F <= 0
};

/// The immutable part of a frame-based tissue. Cheap to move, shares its tables when copied.
class FrameTissueModel {
 public:
  std::int64_t frame_count() const;
  std::int64_t point_count() const;
  /// Frame-point pairs (sum of the points' neighbour counts).
  std::int64_t pair_count() const;
  const FrameTissueOptions& options() const;
  /// Rest positions, 3 per frame, in metres.
  std::span<const double> rest_positions_m() const;
  /// Lumped frame masses, in kilograms (sum: density times the integrated volume).
  std::span<const double> frame_masses_kg() const;
  /// The driven frames, in input order.
  std::span<const std::int32_t> driven_frames() const;
  /// Half-bandwidth of the assembled system in DOFs (0 for cg_block_jacobi).
  std::int64_t half_bandwidth() const;

  const detail::FrameTables& tables() const { return *tables_; }
  explicit FrameTissueModel(std::shared_ptr<const detail::FrameTables> tables) : tables_(std::move(tables)) {}

 private:
  std::shared_ptr<const detail::FrameTables> tables_;
};

/// The state and workspace of one FrameTissueModel, carved from one arena at init.
struct FrameTissueData {
  Arena arena;
  std::span<double> positions_m;        ///< 3 per frame
  std::span<double> orientations_wxyz;  ///< unit quaternion per frame
  std::span<double> velocities;         ///< 6 per frame: m/s then rad/s (world axes)
  /// Force of the tissue on each driven frame's translation after the last step (3 each, in
  /// newtons): what the tissue pulls an attached organ with. Includes the frame's weight share.
  std::span<double> driven_forces_n;
  HealthFlags health;
  FrameStepReport report;
  std::int64_t steps = 0;

  // Workspace (meaningless between steps).
  std::span<double> rotations, inertias, forces, rhs, solution, residual, preconditioned, direction, product;
  std::span<double> free_velocities, backup, blocks, band;
  std::span<double> point_gradients, point_stresses, pair_arms, frame_spins;

  explicit FrameTissueData(Arena block) : arena(std::move(block)) {}
};

/// Builds the model. Errors name the field at fault: a layout whose weights do not sum to one
/// or whose gradients do not sum to zero, a frame index out of range, a frame reached by no
/// point, a material or option out of range, a system too large for the banded solver.
Result<FrameTissueModel> make_frame_tissue_model(const FrameTissueScene& scene, const FrameTissueOptions& options);

/// The data of `model`, at rest with zero velocity.
Result<FrameTissueData> make_frame_tissue_data(const FrameTissueModel& model);

/// Advances the tissue by one step of model.options().step_s under `inputs`.
void step(const FrameTissueModel& model, FrameTissueData& data, const FrameTissueInputs& inputs) noexcept;

/// Elastic energy of the current frames, in joules.
double elastic_energy_j(const FrameTissueModel& model, const FrameTissueData& data) noexcept;

/// Elastic restoring forces -dW/dq at the current frames (6 per frame: force, then torque
/// about the frame's rotation increment), in `forces`; refreshes the workspace's stresses
/// for stiffness_product.
void elastic_forces(const FrameTissueModel& model, FrameTissueData& data, std::span<double> forces) noexcept;

/// out = K dq with K the tangent of the step (material, plus geometric if the options say so)
/// at the state of the last elastic_forces call.
void stiffness_product(const FrameTissueModel& model, FrameTissueData& data, std::span<const double> dq,
                       std::span<double> out) noexcept;

/// Current position of the material point that rests at `rest_m`, whose shape functions are
/// `neighbours` (eq. 3).
Point3 material_point_m(const FrameTissueModel& model, const FrameTissueData& data, const PointNeighbours& neighbours,
                        const Point3& rest_m) noexcept;

}  // namespace nav
