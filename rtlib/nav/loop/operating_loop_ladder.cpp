// The liver step of an operating loop and its ladder's moves between rungs: the liver's state
// (q_big = T q_small up, the M-projection T^T q_big down), the filter (dq and P carried by the
// same map, the prior added in the directions the lower rung lacks) and the needle (its beam,
// layers, path and forces, the same on every rung; the new rung's tissue displacements
// rebuilt). Nothing here allocates, locks or throws.
#include "nav/loop/operating_loop_ladder.hpp"

#include <algorithm>
#include <cmath>

#include "nav/needle/coupled_needle_step.hpp"
#include "nav/reduced/reduced_envelope.hpp"

namespace nav::detail {
namespace {

template <class T>
void copy_span(std::span<const T> from, std::span<T> to) noexcept {
  std::copy_n(from.begin(), std::min(from.size(), to.size()), to.begin());
}

/// out = a x, a rows x cols row-major.
void multiply(std::span<const double> a, int rows, int cols, std::span<const double> x,
              std::span<double> out) noexcept {
  for (int i = 0; i < rows; ++i) {
    double sum = 0.0;
    for (int j = 0; j < cols; ++j) sum += a[static_cast<std::size_t>(i * cols + j)] * x[static_cast<std::size_t>(j)];
    out[static_cast<std::size_t>(i)] = sum;
  }
}

double squared_norm(std::span<const double> x) noexcept {
  double sum = 0.0;
  for (double v : x) sum += v * v;
  return sum;
}

/// The needle's state (beam, layers, path, forces and rows, counters) from one rung's coupled
/// data to another's: the same needle and scene, only the tissue compliance differs.
void copy_needle_state(const ReducedCoupledNeedleData& from, ReducedCoupledNeedleData& to) noexcept {
  const NeedleData& a = from.interaction.needle;
  NeedleData& b = to.interaction.needle;
  copy_span<double>(a.positions_m, b.positions_m);
  copy_span<double>(a.rotations_wxyz, b.rotations_wxyz);
  copy_span<double>(a.velocities_m_s, b.velocities_m_s);
  copy_span<double>(a.angular_velocities_rad_s, b.angular_velocities_rad_s);
  copy_span<double>(a.start_positions_m, b.start_positions_m);
  copy_span<double>(a.start_rotations_wxyz, b.start_rotations_wxyz);
  copy_span<double>(a.start_velocities_m_s, b.start_velocities_m_s);
  copy_span<double>(a.start_angular_velocities_rad_s, b.start_angular_velocities_rad_s);
  b.health = a.health;
  b.report = a.report;
  b.steps = a.steps;
  const NeedleTissueData& i = from.interaction;
  NeedleTissueData& j = to.interaction;
  j.health = i.health;
  j.report = i.report;
  j.steps = i.steps;
  copy_span<LayerState>(i.layers, j.layers);
  copy_span<PathPoint>(i.path, j.path);
  j.tip_anchor = i.tip_anchor;
  copy_span<double>(i.slot_forces, j.slot_forces);
  copy_span<double>(i.applied_forces, j.applied_forces);
  copy_span<ConstraintRow>(i.rows, j.rows);  // the last step's rows: the tick's tip force is read from them
  copy_span<double>(i.row_forces, j.row_forces);
  j.row_count = i.row_count;
  j.point_count = i.point_count;
  copy_span<PointForce>(from.point_forces, to.point_forces);
  to.point_force_count = from.point_force_count;
  to.dropped_point_forces = from.dropped_point_forces;
  to.ticks = from.ticks;
  to.refresh_cursor = from.refresh_cursor;
}

/// Puts the liver state (q, v, d) mapped by `map` (r_to x r_from) into rung `to`, carries the
/// filter and the needle there, and makes it the active rung.
void move_to(const OperatingLoopModel& model, OperatingLoopData& data, int to, const ReducedData& state,
             std::span<const double> map, std::span<const double> added_prior) noexcept {
  const int from = data.active_rung;
  const OperatingLoopRung& source = model.rungs[static_cast<std::size_t>(from)];
  const OperatingLoopRung& target = model.rungs[static_cast<std::size_t>(to)];
  OperatingLoopRungData& a = data.rungs[static_cast<std::size_t>(from)];
  OperatingLoopRungData& b = data.rungs[static_cast<std::size_t>(to)];
  ReducedData& liver = b.liver();
  const int rows = target.reduced.basis_size(), cols = source.reduced.basis_size();
  multiply(map, rows, cols, state.q, liver.q);
  multiply(map, rows, cols, state.q_velocity, liver.q_velocity);
  std::copy_n(state.prescribed_m, 3, liver.prescribed_m);
  liver.report = {};
  liver.steps = state.steps;
  liver.health.clear_all();
  carry_filter(source.filter, a.filter, target.filter, b.filter, map, added_prior, data.transfer_workspace);
  if (b.needle_model) {
    copy_needle_state(*a.needle_model, *b.needle_model);
    // The needle meets the tissue's free motion (coupled_needle.hpp): the source's, carried up.
    const ReducedData& free_from = a.needle_model->free_tissue;
    ReducedData& free_to = b.needle_model->free_tissue;
    multiply(map, rows, cols, free_from.q, free_to.q);
    multiply(map, rows, cols, free_from.q_velocity, free_to.q_velocity);
    std::copy_n(free_from.prescribed_m, 3, free_to.prescribed_m);
    reconstruct_all_displacements_m(target.reduced, free_to, b.needle_model->displacements_m);
    refresh_surfaces(target.needle->coupled.interaction, b.needle_model->interaction, b.needle_model->displacements_m);
  }
  data.active_rung = to;
  data.flagged_steps = 0;
  data.inside_steps = 0;
}

/// Steps rung `rung`'s liver (through its coupled needle when there is one); returns the
/// step's flags and clears them on the liver.
HealthFlags step_rung(const OperatingLoopModel& model, OperatingLoopData& data, int rung,
                      const TissueInputs& inputs) noexcept {
  const OperatingLoopRung& m = model.rungs[static_cast<std::size_t>(rung)];
  OperatingLoopRungData& d = data.rungs[static_cast<std::size_t>(rung)];
  ReducedData& liver = d.liver();
  liver.health.clear_all();
  if (m.needle)
    step_tissue(m.needle->coupled, *d.needle_model, inputs);
  else
    step(m.reduced, liver, inputs);
  const HealthFlags raised = liver.health;
  liver.health.clear_all();
  return raised;
}

/// Counts the steps whose state, M-projected on the rung below, is inside that rung's bounds
/// and represented by it, and steps down when they are enough.
void consider_stepping_down(const OperatingLoopModel& model, OperatingLoopData& data) noexcept {
  const ReducedLadderOptions& o = model.ladder->options();
  const int from = data.active_rung;
  if (o.de_escalate_after_steps == 0 || from == 0) return;
  const OperatingLoopRung& rung = model.rungs[static_cast<std::size_t>(from)];
  const ReducedData& liver = data.active().liver();
  ReducedData& projected = data.rungs[static_cast<std::size_t>(from - 1)].lookahead;  // scratch
  const int lower = model.rungs[static_cast<std::size_t>(from - 1)].reduced.basis_size();
  multiply(rung.down_to_below, lower, rung.reduced.basis_size(), liver.q, projected.q);
  const double total = squared_norm(liver.q), kept = squared_norm(projected.q);
  const double residual = total > 0.0 ? std::sqrt(std::max(0.0, total - kept) / total) : 0.0;
  const bool fits = model.ladder->envelope_ratio(from - 1, projected.q) <= o.de_escalation_envelope_ratio &&
                    residual <= o.de_escalation_residual;
  data.inside_steps = fits ? data.inside_steps + 1 : 0;
  if (data.inside_steps < o.de_escalate_after_steps) return;
  move_to(model, data, from - 1, liver, rung.down_to_below, {});
  ++data.outputs.de_escalations;
}

}  // namespace

HealthFlags step_liver(const OperatingLoopModel& model, OperatingLoopData& data, const TissueInputs& inputs) noexcept {
  const int rung = data.active_rung;
  if (!model.ladder) return step_rung(model, data, rung, inputs);
  OperatingLoopRungData& active = data.active();
  copy_state(active.liver(), active.lookahead);  // the state before the step (the scratch is free until the look-ahead)
  HealthFlags raised = step_rung(model, data, rung, inputs);
  if (raised.has(HealthFlag::bad_sample)) return raised;  // refused, the state untouched
  const ReducedLadderOptions& o = model.ladder->options();
  const bool fired = detail::reduced_indicator_fired(raised);
  data.flagged_steps = fired ? data.flagged_steps + 1 : 0;
  const bool escalate = fired && o.escalation_allowed && rung + 1 < static_cast<int>(model.rungs.size()) &&
                        data.flagged_steps >= o.escalate_after_steps;
  if (!escalate) {
    consider_stepping_down(model, data);
    return raised;
  }
  const OperatingLoopRung& upper = model.rungs[static_cast<std::size_t>(rung + 1)];
  move_to(model, data, rung + 1, active.lookahead, upper.up_from_below, upper.unseen_prior);
  ++data.outputs.escalations;
  const HealthFlags again = step_rung(model, data, rung + 1, inputs);
  data.flagged_steps = detail::reduced_indicator_fired(again) ? 1 : 0;
  raised.merge(again);
  raised.raise(HealthFlag::reduced_escalated);
  return raised;
}

}  // namespace nav::detail
