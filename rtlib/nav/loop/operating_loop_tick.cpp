// Step time of the operating loop: the push_* calls that take the I/O thread's samples, and
// the tick, with the needle model's step when there is one. Nothing here allocates, locks,
// throws or makes a system call; every loop has a fixed trip count (the pending queue's
// capacity, the look-ahead's step count, r, the needle's nodes and rows).
#include <algorithm>
#include <cmath>
#include <span>

#include "nav/loop/operating_loop.hpp"
#include "nav/loop/operating_loop_ladder.hpp"
#include "nav/needle/coupled_needle_step.hpp"

namespace nav {
namespace {

constexpr TimeNs kNever = std::numeric_limits<TimeNs>::min();

Point3 to_point(const Eigen::Vector3d& v) noexcept { return {v[0], v[1], v[2]}; }

double distance_m(const Point3& a, const Point3& b) noexcept {
  return std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
}

/// The status of a tracked tool: the lookup's flags and those of the samples pushed since the
/// last tick (which are then cleared).
InputStatus tool_status(const PoseTrack& track, const PoseQuery& query, HealthFlags& push_flags) noexcept {
  InputStatus status;
  status.flags = query.flags;
  status.flags.merge(push_flags);
  status.degraded = query.degraded || !push_flags.healthy();
  status.age_ns = track.size() == 0 ? std::numeric_limits<TimeNs>::max() : query.age_ns;
  push_flags.clear_all();
  return status;
}

/// The diaphragm displacement at now + horizon: the newest marker sample moved on by the
/// breathing model's change from that sample's time, so that irregular breathing (a deep
/// breath, a cough) is followed at once while the model compensates the delay and looks
/// ahead. Rest when the marker was never seen.
Point3 diaphragm_m(const OperatingLoopOptions& o, const OperatingLoopData& data, TimeNs now_ns,
                   TimeNs horizon_ns) noexcept {
  if (data.respiratory_newest_ns == kNever) return {0.0, 0.0, 0.0};
  const double change_m = data.breathing.predict(now_ns, horizon_ns).displacement_m -
                          data.breathing.predict(data.respiratory_newest_ns, 0).displacement_m;
  return to_point(o.diaphragm_per_marker * (data.respiratory_newest_m + change_m - o.respiratory_reference_m));
}

/// An observation carried from its capture time to the liver step's: moved by the diaphragm
/// lift's motion of the tumour in between (L_p times the change of the diaphragm displacement),
/// the bulk of the breathing's motion over the capture and segmentation delay.
Point3 carried_to_step(const OperatingLoopModel& model, const ReducedKalmanModel& filter, const OperatingLoopData& data,
                       const PendingObservation& seen, const Point3& diaphragm_now_m) noexcept {
  Point3 out = seen.position_m;
  if (!filter.has_lift) return out;
  const Point3 then_m = diaphragm_m(model.options, data, seen.time_ns, 0);
  for (std::size_t c = 0; c < 3; ++c)
    for (std::size_t k = 0; k < 3; ++k) out[c] += filter.lift_rows[3 * c + k] * (diaphragm_now_m[k] - then_m[k]);
  return out;
}

/// Point 0 of the filter at reduced coordinates q + dq_scale dq and diaphragm displacement d.
Point3 tumour_at(const ReducedKalmanModel& f, std::span<const double> q, double dq_scale, std::span<const double> dq,
                 const double (&d)[3]) noexcept {
  const auto r = static_cast<std::size_t>(f.r);
  Point3 out{};
  for (std::size_t c = 0; c < 3; ++c) {
    double v = f.rest_m[c];
    const double* row = f.rows.data() + c * r;
    for (std::size_t j = 0; j < r; ++j) v += row[j] * (q[j] + dq_scale * dq[j]);
    if (f.has_lift)
      for (std::size_t k = 0; k < 3; ++k) v += f.lift_rows[3 * c + k] * d[k];
    out[c] = v;
  }
  return out;
}

/// The covariance of point 0 after `decay_squared` of the Gauss-Markov time update:
/// a^2k H P H^T + (1 - a^2k) H S H^T, from the current H P H^T.
std::array<double, 9> covariance_ahead(const ReducedKalmanModel& f, const std::array<double, 9>& now_m2,
                                       double decay_squared) noexcept {
  const auto r = static_cast<std::size_t>(f.r);
  std::array<double, 9> out{};
  for (std::size_t c = 0; c < 3; ++c)
    for (std::size_t e = 0; e < 3; ++e) {
      double prior = 0.0;
      for (std::size_t j = 0; j < r; ++j) prior += f.rows[c * r + j] * f.rows[e * r + j] * f.prior_variance[j];
      out[3 * c + e] = decay_squared * now_m2[3 * c + e] + (1.0 - decay_squared) * prior;
    }
  return out;
}

/// The ligaments' step at the active liver as it stands (their attachment nodes rebuilt from
/// its state): their forces on the liver for its step that follows (none without ligaments).
/// Their flags join `flags`.
std::span<const PointForce> ligaments_tick(const OperatingLoopModel& model, OperatingLoopData& data,
                                           HealthFlags& flags) noexcept {
  if (!model.ligaments) return {};
  const OrganLigaments& ligaments = *model.ligaments;
  OperatingLoopLigamentsData& state = *data.ligaments;
  const std::vector<std::int32_t>& nodes = ligaments.attachment.nodes;
  reconstruct_displacements_m(model.rungs[static_cast<std::size_t>(data.active_rung)].reduced, data.active().liver(),
                              nodes, state.node_displacements_m);
  const std::vector<double>& rest_m = ligaments.attachment.node_rest_positions_m;
  for (std::size_t k = 0; k < nodes.size(); ++k)
    for (std::size_t c = 0; c < 3; ++c)
      state.organ_positions_m[3 * static_cast<std::size_t>(nodes[k]) + c] =
          rest_m[3 * k + c] + state.node_displacements_m[3 * k + c];
  step_attached(ligaments.model, state.tissue, ligaments.attachment, state.buffers, state.organ_positions_m, 1.0);
  flags.merge(state.tissue.health);
  state.tissue.health.clear_all();
  return state.buffers.point_forces;
}

/// The liver step of a tissue tick: diaphragm (with the ligaments' and the needle's forces),
/// reduced step (on the ladder's rung, which may change), filter predict, pending
/// observations, then the look-ahead to now + display latency.
void tissue_tick(const OperatingLoopModel& model, OperatingLoopData& data, TimeNs now_ns) noexcept {
  const OperatingLoopOptions& o = model.options;
  OperatingLoopOutputs& out = data.outputs;
  TissueInputs inputs;
  inputs.prescribed_displacement_m = diaphragm_m(o, data, now_ns, 0);
  HealthFlags ligaments;
  inputs.point_forces = ligaments_tick(model, data, ligaments);
  HealthFlags tissue = detail::step_liver(model, data, inputs);
  tissue.merge(ligaments);
  const OperatingLoopRung& rung = model.rungs[static_cast<std::size_t>(data.active_rung)];
  OperatingLoopRungData& state = data.active();
  ReducedData& liver = state.liver();
  if (state.needle_model)  // the look-ahead carries the forces of this step (the needle's, then the ligaments')
    inputs.point_forces =
        std::span<const PointForce>(state.needle_model->point_forces.data(), state.needle_model->point_force_count);
  predict(rung.filter, state.filter, liver);
  tissue.merge(state.filter.health);
  state.filter.health.clear_all();

  for (std::size_t i = 0; i < data.pending_count; ++i) {
    const PendingObservation& seen = data.pending[i];
    update(rung.filter, state.filter, 0,
           carried_to_step(model, rung.filter, data, seen, inputs.prescribed_displacement_m), seen.time_ns);
  }
  data.pending_count = 0;
  data.ultrasound_push_flags.merge(state.filter.health);  // rejected observations are the ultrasound's fault
  state.filter.health.clear_all();
  const PointEstimate estimate = estimate_point(rung.filter, state.filter, 0);

  copy_state(liver, state.lookahead);
  const TimeNs step_ns = o.tick_period_ns * o.tissue_every_ticks;
  for (int j = 1; j <= model.lookahead_steps; ++j) {
    const TimeNs horizon_ns = std::min(step_ns * j, o.display_latency_ns);
    inputs.prescribed_displacement_m = diaphragm_m(o, data, now_ns, horizon_ns);
    step(rung.reduced, state.lookahead, inputs);
  }
  tissue.merge(state.lookahead.health);
  state.lookahead.health.clear_all();

  out.tissue = tissue;
  out.tissue_time_ns = now_ns;
  ++out.tissue_steps;
  out.liver_rung = data.active_rung;
  std::copy(std::begin(liver.prescribed_m), std::end(liver.prescribed_m), out.diaphragm_m.begin());
  for (std::size_t j = 0; j < liver.q.size(); ++j) out.liver_q[j] = liver.q[j] + state.filter.correction[j];
  out.tumour_now_m = estimate.position_m;
  out.tumour_now_covariance_m2 = estimate.covariance_m2;
  out.tumour_ahead_m = tumour_at(rung.filter, state.lookahead.q, rung.lookahead_decay, state.filter.correction,
                                 state.lookahead.prescribed_m);
  out.tumour_ahead_covariance_m2 =
      covariance_ahead(rung.filter, estimate.covariance_m2, rung.lookahead_decay * rung.lookahead_decay);
}

/// Whether a pose holds no NaN or infinity.
bool finite(const RigidPose& pose) noexcept {
  return pose.position_m.allFinite() && pose.rotation.coeffs().allFinite();
}

/// The needle model's step: its base at the tracked pose when that is good (held at the last
/// good one otherwise). A pose farther than the needle's one-step limit places a free needle
/// there; a needle holding tissue glides toward it by half the limit per tick (flagged).
/// Idle until the first good pose.
void needle_tick(const OperatingLoopNeedleModel& needle_model, OperatingLoopData& data,
                 const PoseQuery& tracked) noexcept {
  if (!tracked.degraded && finite(tracked.pose)) {
    data.needle_base = compose(tracked.pose, needle_model.marker_from_base);
    data.needle_acquired = true;
  }
  if (!data.needle_acquired) return;
  ReducedCoupledNeedleData& coupled = *data.active().needle_model;
  const NeedleParameters& p = needle_model.coupled.interaction.needle.parameters;
  const NeedleData& needle = coupled.interaction.needle;
  const RigidPose from{node_position_m(needle.positions_m, 0), node_rotation(needle.rotations_wxyz, 0)};
  const RigidPose& to = data.needle_base;
  const double jump_m = (to.position_m - from.position_m).norm() +
                        p.length_m * relative_rotation_vector(from.rotation, to.rotation).norm();
  RigidPose base = to;
  if (jump_m > p.max_pose_jump_m &&
      !place_free_needle(needle_model.coupled.interaction, coupled.interaction, to_needle_pose(to))) {
    base = geodesic(from, to, 0.5 * p.max_pose_jump_m / jump_m);
    coupled.interaction.health.raise(HealthFlag::pose_jump_rejected);
  }
  NeedleInputs inputs;
  inputs.base = to_needle_pose(base);
  step_needle(needle_model.coupled, coupled, inputs);
  data.outputs.needle_shape.base_pose = base;
}

/// The needle model's outputs after the tick (shape, forces, depth, punctures, flags, which
/// are then cleared), and the modelled tip in place of the rigid one.
void needle_outputs(const OperatingLoopNeedleModel& needle_model, OperatingLoopData& data,
                    Point3 rigid_tip_m) noexcept {
  OperatingLoopOutputs& out = data.outputs;
  NeedleShapeOutputs& shape = out.needle_shape;
  NeedleTissueData& interaction = data.active().needle_model->interaction;
  shape.flags = interaction.health;
  interaction.health.clear_all();
  interaction.needle.health.clear_all();
  if (!data.needle_acquired) return;
  const NeedleTissueModel& m = needle_model.coupled.interaction;
  shape.node_count = m.needle.node_count();
  for (int n = 0; n < shape.node_count; ++n)
    shape.centreline_m[static_cast<std::size_t>(n)] = to_point(node_position_m(interaction.needle.positions_m, n));
  shape.tip_force_n = to_point(tip_force_n(m, interaction));
  // The needle's report holds the first element's force at the base node: the holder's force on
  // the needle (it points down the insertion when the tissue resists); the holder feels its opposite.
  for (std::size_t c = 0; c < 3; ++c) shape.base_force_n[c] = -interaction.needle.report.base_force_n[c];
  shape.tip_depth_m = std::max(0.0, interaction.report.tip_depth_m);
  shape.punctures = interaction.report.punctures;
  const Point3& tip_m = shape.centreline_m[static_cast<std::size_t>(shape.node_count - 1)];
  for (std::size_t c = 0; c < 3; ++c) out.needle_tip_ahead_m[c] += tip_m[c] - rigid_tip_m[c];
  out.needle_tip_m = tip_m;
}

/// The ultrasound's status: age of the newest accepted observation, and the flags of the
/// observations since the last tick (rejections, overruns).
InputStatus ultrasound_status(const OperatingLoopModel& model, OperatingLoopData& data, TimeNs now_ns) noexcept {
  InputStatus status;
  status.flags = data.ultrasound_push_flags;
  data.ultrasound_push_flags.clear_all();
  const TimeNs last_ns = data.active().filter.last_update_ns;
  if (last_ns == kNever) {
    status.flags.raise(HealthFlag::missing_input);
  } else {
    status.age_ns = now_ns - last_ns;
    if (status.age_ns > model.options.ultrasound_max_age_ns) status.flags.raise(HealthFlag::stale_input);
  }
  status.degraded = !status.flags.healthy();
  return status;
}

}  // namespace

void push_needle_pose(const OperatingLoopModel& model, OperatingLoopData& data, const TimedPose& sample) noexcept {
  data.needle_push_flags.merge(
      data.needle.push({sample.time_ns, compose(model.options.model_from_tracker, sample.pose)}));
}

void push_probe_pose(const OperatingLoopModel& model, OperatingLoopData& data, const TimedPose& sample) noexcept {
  data.probe_push_flags.merge(
      data.probe.push({sample.time_ns, compose(model.options.model_from_tracker, sample.pose)}));
}

void push_respiratory_sample(const OperatingLoopModel& model, OperatingLoopData& data, TimeNs time_ns,
                             const Eigen::Vector3d& position_m) noexcept {
  const HealthFlags flags = data.breathing.push_position(time_ns, position_m);
  data.respiratory_push_flags.merge(flags);
  if (!flags.healthy()) return;
  data.respiratory_newest_ns = time_ns;
  data.respiratory_newest_m = model.breathing_axis.dot(position_m);
}

void push_tumour_observation(OperatingLoopData& data, TimeNs time_ns, const Point3& position_m) noexcept {
  if (data.pending_count == data.pending.size()) {  // full: the oldest observation is dropped
    std::copy(data.pending.begin() + 1, data.pending.end(), data.pending.begin());
    --data.pending_count;
    data.ultrasound_push_flags.raise(HealthFlag::buffer_overrun);
  }
  data.pending[data.pending_count++] = {time_ns, position_m};
}

void liver_displacements_m(const OperatingLoopModel& model, const OperatingLoopOutputs& outputs,
                           LiverDisplayScratch& scratch, std::span<const std::int32_t> nodes,
                           std::span<double> out_xyz) noexcept {
  const auto rung =
      static_cast<std::size_t>(std::clamp(outputs.liver_rung, 0, static_cast<int>(model.rungs.size()) - 1));
  ReducedData& state = scratch.rungs[rung];
  std::copy_n(outputs.liver_q.begin(), state.q.size(), state.q.begin());
  std::copy(outputs.diaphragm_m.begin(), outputs.diaphragm_m.end(), std::begin(state.prescribed_m));
  reconstruct_displacements_m(model.rungs[rung].reduced, state, nodes, out_xyz);
}

void tick(const OperatingLoopModel& model, OperatingLoopData& data, TimeNs now_ns) noexcept {
  const OperatingLoopOptions& o = model.options;
  OperatingLoopOutputs& out = data.outputs;
  out.loop.clear_all();
  if (out.ticks > 0 && now_ns <= data.last_tick_ns) out.loop.raise(HealthFlag::clock_went_backwards);
  data.last_tick_ns = now_ns;
  out.time_ns = now_ns;

  const TimeNs ahead_ns = now_ns + o.display_latency_ns;
  const PoseQuery needle = data.needle.sample_at(now_ns);
  out.needle = tool_status(data.needle, needle, data.needle_push_flags);
  const OperatingLoopNeedleModel* needle_model = model.rungs[static_cast<std::size_t>(data.active_rung)].needle.get();
  const Eigen::Vector3d& tip_in_marker_m = needle_model ? needle_model->tip_in_marker_m : o.needle_tip_in_marker_m;
  out.needle_tip_m = to_point(needle.pose.rotation * tip_in_marker_m + needle.pose.position_m);
  const RigidPose needle_ahead = data.needle.sample_at(ahead_ns).pose;
  out.needle_tip_ahead_m = to_point(needle_ahead.rotation * tip_in_marker_m + needle_ahead.position_m);
  if (needle_model) needle_tick(*needle_model, data, needle);
  const PoseQuery probe = data.probe.sample_at(now_ns);
  out.probe = tool_status(data.probe, probe, data.probe_push_flags);
  out.probe_pose = probe.pose;

  const BreathingEstimate breathing = data.breathing.predict(now_ns, 0);
  out.breathing_phase_rad = breathing.phase_rad;
  out.respiratory.flags = breathing.flags;
  out.respiratory.flags.merge(data.respiratory_push_flags);
  data.respiratory_push_flags.clear_all();
  out.respiratory.degraded = !breathing.ready || !out.respiratory.flags.healthy();
  out.respiratory.age_ns =
      data.respiratory_newest_ns == kNever ? std::numeric_limits<TimeNs>::max() : now_ns - data.respiratory_newest_ns;

  if (out.ticks % o.tissue_every_ticks == 0) tissue_tick(model, data, now_ns);
  // The needle as the tick leaves it, on the rung the liver step may have moved it to.
  if (model.has_needle())
    needle_outputs(*model.rungs[static_cast<std::size_t>(data.active_rung)].needle, data, out.needle_tip_m);
  out.ultrasound = ultrasound_status(model, data, now_ns);

  out.tip_to_tumour_m = distance_m(out.needle_tip_m, out.tumour_now_m);
  out.tip_to_tumour_ahead_m = distance_m(out.needle_tip_ahead_m, out.tumour_ahead_m);
  out.degraded = out.needle.degraded || out.probe.degraded || out.respiratory.degraded || out.ultrasound.degraded ||
                 !out.tissue.healthy() || !out.loop.healthy() || !out.needle_shape.flags.healthy();
  ++out.ticks;
}

}  // namespace nav
