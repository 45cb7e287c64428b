#pragma once
// The escalation ladder of the reduced liver: reduced models of growing basis size on one
// mesh and scene, optionally topped by the full-order TetFemModel. The ladder steps its
// active rung; when that rung's indicator fires (reduced_out_of_envelope,
// reduced_error_over_bound, or a step undone for a non-finite state) and the scene allows
// it, the state before the step is carried up one rung (q_big = T q_small with T = U_big^T M U_small, the M-projection;
// to the full order u = U q + L d, v = U q_dot) and the step is redone there. Optionally the ladder steps back down
// once the state, M-projected on the rung below, has stayed inside that rung's envelope and representable by it.
// Model/Data: every rung's data is allocated at init; step() is noexcept, allocation-free and bitwise repeatable.
#include <cstdint>
#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "nav/core/arena.hpp"
#include "nav/core/error.hpp"
#include "nav/core/health.hpp"
#include "nav/reduced/reduced_model.hpp"
#include "nav/tissue/tet_fem_model.hpp"

namespace nav {

namespace detail {
struct ReducedLadderTables;
}

/// One reduced rung to build: its basis (with force reduction and training envelope) and
/// its solver settings. Every rung of a ladder has the same step_s and integrator.
struct ReducedRungSpec {
  ReducedBasis basis;
  ReducedSolverOptions options;
};

/// How a ladder moves between its rungs.
struct ReducedLadderOptions {
  /// The scene's switch: false keeps the ladder on its rung, raising the indicator's flag only.
  bool escalation_allowed = true;
  /// Consecutive steps with the indicator up before the ladder escalates (at least 1); the
  /// step that reaches the count is redone one rung up.
  int escalate_after_steps = 1;
  /// Consecutive steps whose state, M-projected on the rung below, is inside both bounds
  /// below before the ladder steps down; 0 never steps down.
  int de_escalate_after_steps = 0;
  /// The projected |q_i| / training bound_i must stay at or below this; it must be below the
  /// lower rung's envelope_factor (hysteresis: the ladder does not step down to re-escalate).
  double de_escalation_envelope_ratio = 1.0;
  /// The part of the displacement the lower rung cannot represent, |u - P u|_M / |U q|_M, must
  /// stay at or below this (it is the jump that stepping down would make).
  double de_escalation_residual = 0.05;
};

/// The immutable part of a ladder: its rungs' models and the transfer operators between
/// neighbouring rungs. Cheap to move, shares its tables when copied.
class ReducedLadderModel {
 public:
  /// Reduced rungs, plus one when the full order tops the ladder.
  int rung_count() const;
  int reduced_rung_count() const;
  bool has_full_order() const;
  std::int64_t node_count() const;
  const ReducedLadderOptions& options() const;
  const ReducedModel& reduced_rung(int rung) const;
  /// The full-order rung; only when has_full_order().
  const TetFemModel& full_order() const;
  /// 1 - the smallest squared M-norm of a column of U_small carried to the rung above (0 when
  /// the smaller basis lies in the larger one's span, as for leading columns of one basis).
  double transfer_loss(int lower_rung) const;
  /// T = U_big^T M U_small from reduced rung `lower_rung` to the one above (r_big x r_small,
  /// row-major): q_big = T q_small, and the M-projection back is q_small = T^T q_big.
  std::span<const double> transfer(int lower_rung) const;
  /// The indicator of reduced rung `rung` at coordinates q: the largest |q_i| / training
  /// bound_i, a direction with a zero bound counting as twice the envelope factor when it moves.
  double envelope_ratio(int rung, std::span<const double> q) const;

  const detail::ReducedLadderTables& tables() const { return *tables_; }
  explicit ReducedLadderModel(std::shared_ptr<const detail::ReducedLadderTables> tables) : tables_(std::move(tables)) {}

 private:
  std::shared_ptr<const detail::ReducedLadderTables> tables_;
};

/// What the last ladder step did.
struct ReducedLadderReport {
  int rung = 0;               ///< the rung whose result the state is
  bool escalated = false;     ///< the step was redone one rung up
  bool de_escalated = false;  ///< after the step the ladder moved one rung down
  /// The indicator of the rung that first took the step: its largest |q_i| / training bound_i.
  double envelope_ratio = 0.0;
  /// Its estimated error (0 without a calibrated estimate), metres.
  double estimated_error_m = 0.0;
  /// On a rung with one below (and de-escalation on): the M-projection of the state on it, its
  /// envelope ratio and the relative part it cannot represent.
  double projected_envelope_ratio = 0.0;
  double projection_residual = 0.0;
};

/// The data of every rung, allocated at init, and the ladder's position on them.
struct ReducedLadderData {
  std::vector<ReducedData> reduced;  ///< one per reduced rung; never resized after init
  std::optional<TetFemData> full;    ///< the full-order rung's data, when the ladder has one
  int active_rung = 0;
  int flagged_steps = 0;   ///< consecutive steps with the indicator up
  int inside_steps = 0;    ///< consecutive steps fit for stepping down
  std::int64_t steps = 0;  ///< steps taken (refused steps not counted)
  std::int64_t escalations = 0, de_escalations = 0;
  HealthFlags health;  ///< raised by steps, cleared by the caller
  ReducedLadderReport report;
  Arena arena;

  // Workspace (meaningless between steps): the state before the step and a projection.
  std::span<double> saved_q, saved_velocity, projected_q, projected_velocity;
  double saved_prescribed_m[3] = {0.0, 0.0, 0.0};
  double prescribed_m[3] = {0.0, 0.0, 0.0};  ///< the diaphragm displacement of the state

  explicit ReducedLadderData(Arena block) : arena(std::move(block)) {}
};

/// Builds every rung on `mesh` and `scene`: rungs[i] reduced with `solver`'s element law,
/// of strictly growing basis size, and, with `full_order_on_top`, the TetFemModel of `solver`
/// (its step_s and integrator must match the rungs'). Precomputes the transfer operators.
/// Errors name the field at fault (rungs[i].basis..., step_s, integrator, ladder options).
Result<ReducedLadderModel> make_reduced_ladder_model(const TetMesh& mesh, const TissueScene& scene,
                                                     const TissueSolverOptions& solver,
                                                     std::span<const ReducedRungSpec> rungs, bool full_order_on_top,
                                                     const ReducedLadderOptions& options);

/// The data of every rung, at rest, on rung 0.
Result<ReducedLadderData> make_reduced_ladder_data(const ReducedLadderModel& model);

/// Advances the active rung by one step under `inputs`, escalating or stepping down as the
/// options say. A refused step (bad_sample) leaves the state and the rung untouched. The
/// rung's flags are merged into data.health; an escalation adds reduced_escalated and keeps
/// reduced_out_of_envelope visible.
void step(const ReducedLadderModel& model, ReducedLadderData& data, const TissueInputs& inputs) noexcept;

/// Carries the state of the active rung to `rung`, one rung at a time (up by the transfer
/// operators, down by the M-projection), and makes it the active one. Counters are reset.
void move_to_rung(const ReducedLadderModel& model, ReducedLadderData& data, int rung) noexcept;

/// Displacements from rest (3 per node, metres) of `nodes` from the active rung, into
/// out_xyz (3 per node).
void reconstruct_displacements_m(const ReducedLadderModel& model, const ReducedLadderData& data,
                                 std::span<const std::int32_t> nodes, std::span<double> out_xyz) noexcept;

/// Displacements from rest of every node (3 node_count values) from the active rung.
void reconstruct_all_displacements_m(const ReducedLadderModel& model, const ReducedLadderData& data,
                                     std::span<double> out) noexcept;

}  // namespace nav
