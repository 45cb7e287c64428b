#pragma once
// The online reduced-order tissue model: the displacement u = U q + L d of a ReducedBasis,
// advanced by implicit Euler or quasi-static Newton iterations on the r x r system, under
// the same TissueInputs as the full-order models. Model/Data: the model is built once and
// immutable; the data is one arena; step() is noexcept, allocation-free, fixed-cost and
// bitwise repeatable. Each step checks its state against the training envelope.
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

#include "nav/core/arena.hpp"
#include "nav/core/error.hpp"
#include "nav/core/health.hpp"
#include "nav/core/kernel_isa.hpp"
#include "nav/mesh/tet_mesh.hpp"
#include "nav/reduced/reduced_basis.hpp"
#include "nav/tissue/tissue_scene.hpp"

namespace nav {

namespace detail {
struct ReducedTables;
}

/// The time integration of a reduced step.
enum class ReducedIntegrator {
  implicit_euler,  ///< backward Euler on the reduced velocity
  quasi_static,    ///< Newton iterations towards equilibrium (Rayleigh damping relaxes them)
};

/// Numerical settings of a reduced model.
struct ReducedSolverOptions {
  ReducedIntegrator integrator = ReducedIntegrator::implicit_euler;
  double step_s = 0.001;
  int newton_iterations = 1;  ///< fixed count, at least 1
  /// The rest tangent U^T K U factored once at init, or the tangent of the current state
  /// rebuilt and factored (LLT) at every Newton iteration.
  bool frozen_tangent = true;
  double rayleigh_mass_per_s = 0.0, rayleigh_stiffness_s = 0.0;
  /// |q_i| beyond envelope_factor * training_q_bound_i raises reduced_out_of_envelope; the
  /// next step then rebuilds its tangent even when frozen_tangent is set. Beyond 10 times
  /// that, q_i is held at the limit with zero rate (no run-away in an untrained direction).
  double envelope_factor = 1.5;
  /// With a calibrated error estimate (ReducedBasis::error_calibration): an estimated error
  /// beyond this (metres) raises reduced_error_over_bound, on which a ladder escalates.
  double error_bound_m = 2e-3;
  /// The instruction set of the cubature kernels: every choice gives the same bits; `best`
  /// is the widest this CPU runs (kernel_isa.hpp).
  KernelIsa kernel_isa = KernelIsa::best;
};

/// What the last reduced step did.
struct ReducedStepReport {
  /// Relative residual of the reduced equations at the start of the last Newton iteration:
  /// |r| / (|h f| + |v - v0|) for implicit Euler, |r| / (|f| + |f_external|) quasi-static.
  double relative_residual = 0.0;
  /// The largest |q_i| / training_q_bound_i (0 without a training envelope).
  double envelope_ratio = 0.0;
  bool out_of_envelope = false;
  int inverted_samples = 0;  ///< sampled tetrahedra with det F <= 0
  /// With a calibrated error estimate: the displacement the basis misses under the step's
  /// point forces, as an estimate of the largest nodal error against the full order
  /// (metres), and whether it passed its bound.
  double estimated_error_m = 0.0;
  bool error_over_bound = false;
};

/// The immutable part of a reduced tissue model. Cheap to move, shares its tables when copied.
class ReducedModel {
 public:
  std::int64_t node_count() const;
  int basis_size() const;
  /// Bytes of the model's tables.
  std::int64_t memory_bytes() const;
  const ReducedSolverOptions& options() const;
  ReducedForceKind force_kind() const;
  int sample_count() const;

  const detail::ReducedTables& tables() const { return *tables_; }
  explicit ReducedModel(std::shared_ptr<const detail::ReducedTables> tables) : tables_(std::move(tables)) {}

 private:
  std::shared_ptr<const detail::ReducedTables> tables_;
};

/// The state and workspace of one ReducedModel, carved from one arena at init.
struct ReducedData {
  Arena arena;
  std::span<double> q;                       ///< reduced coordinates (r)
  std::span<double> q_velocity;              ///< their rates (r), per second
  double prescribed_m[3] = {0.0, 0.0, 0.0};  ///< the diaphragm displacement d of the state
  HealthFlags health;                        ///< raised by steps, cleared by the caller
  ReducedStepReport report;                  ///< what the last step did
  std::int64_t steps = 0;                    ///< steps taken (refused steps not counted)

  // Workspace (meaningless between steps).
  std::span<double> q_start, v_start, v_iterate, force, external, residual, correction, tangent, factor;
  std::span<double> sample_displacements, sample_rotations, sample_tangent_rows, monomials;

  explicit ReducedData(Arena block) : arena(std::move(block)) {}
};

/// Builds the model from a basis of `mesh` and `scene` (checked by fingerprint and sizes).
/// Errors name the field at fault.
Result<ReducedModel> make_reduced_model(const TetMesh& mesh, const TissueScene& scene,
                                        const TissueSolverOptions& solver, const ReducedBasis& basis,
                                        const ReducedSolverOptions& options);

/// `model` with other solver options: its tables copied and its frozen tangent factored again
/// (e.g. a quasi-static twin of a dynamic model, for its static compliance). Init time; errors
/// name the option at fault.
Result<ReducedModel> with_solver_options(const ReducedModel& model, const ReducedSolverOptions& options);

/// The data of `model`, at rest with zero velocity.
Result<ReducedData> make_reduced_data(const ReducedModel& model);

/// Advances the reduced model by one step of model.options().step_s under `inputs` (its probe
/// is ignored: a scene with a probe is refused at build). A step with a non-finite or
/// out-of-range input is refused (bad_sample) with the state untouched; one that would leave a
/// non-finite state is undone (non_finite_state). The prescribed nodes' motion enters through
/// the lift without inertia (the diaphragm moves slowly against the step).
void step(const ReducedModel& model, ReducedData& data, const TissueInputs& inputs) noexcept;

/// Copies the state a step starts from (q, its rates, the diaphragm displacement, the step
/// count and report) of `from` into `to`, data of the same model; clears `to`'s health flags.
/// Allocation-free.
void copy_state(const ReducedData& from, ReducedData& to) noexcept;

/// Displacements from rest (3 per node, metres) of `nodes`, into out_xyz (3 per node).
void reconstruct_displacements_m(const ReducedModel& model, const ReducedData& data,
                                 std::span<const std::int32_t> nodes, std::span<double> out_xyz) noexcept;

/// Displacements from rest of every node (3 node_count values).
void reconstruct_all_displacements_m(const ReducedModel& model, const ReducedData& data,
                                     std::span<double> out) noexcept;

/// The basis rows of a fixed set of nodes (a display surface), laid out for a fast
/// reconstruction: panels of 8 values, each column's 8 values contiguous. Built at init.
struct ReducedDisplaySet {
  std::vector<std::int32_t> nodes;
  int basis_size = 0;
  std::vector<double> panels;       ///< ceil(3 nodes / 8) panels of r x 8 basis values
  std::vector<double> lift_panels;  ///< ceil(3 nodes / 8) panels of 3 x 8 lift values (empty without a lift)
};

/// The display set of `nodes` (each a node of the model), or an Error naming the bad node.
Result<ReducedDisplaySet> make_reduced_display_set(const ReducedModel& model, std::span<const std::int32_t> nodes);

/// Displacements from rest (3 per node, metres) of the display set's nodes, into out_xyz (the
/// first min(out_xyz.size(), 3 nodes) values). Each value sums over the basis columns in
/// order: it can differ from reconstruct_displacements_m in the last bits. Does nothing when
/// the set was built for another basis size.
void reconstruct_display_m(const ReducedModel& model, const ReducedData& data, const ReducedDisplaySet& display,
                           std::span<double> out_xyz) noexcept;

}  // namespace nav
