// Step-time moves of a ReducedLadderModel: the step of the active rung, the escalation that
// redoes it one rung up from the state before it, the M-projection that steps back down,
// and the reconstruction from whichever rung is active.
#include <algorithm>
#include <cmath>

#include "nav/reduced/reduced_envelope.hpp"
#include "nav/reduced/reduced_ladder_tables.hpp"

namespace nav {
namespace {

using detail::ReducedLadderTables;

bool is_reduced(const ReducedLadderTables& t, int rung) { return rung < static_cast<int>(t.rungs.size()); }

int size_of(const ReducedLadderTables& t, int rung) { return t.sizes[static_cast<std::size_t>(rung)]; }

double dot(const double* a, const double* b, int n) {
  double sum = 0.0;
  for (int i = 0; i < n; ++i) sum += a[i] * b[i];
  return sum;
}

/// out = a x, a rows x cols row-major.
void multiply(const std::vector<double>& a, int rows, int cols, std::span<const double> x, std::span<double> out) {
  for (int i = 0; i < rows; ++i)
    out[static_cast<std::size_t>(i)] = dot(a.data() + static_cast<std::size_t>(i * cols), x.data(), cols);
}

/// out = a^T x, a rows x cols row-major.
void multiply_transposed(const std::vector<double>& a, int rows, int cols, std::span<const double> x,
                         std::span<double> out) {
  std::fill(out.begin(), out.begin() + cols, 0.0);
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < cols; ++j)
      out[static_cast<std::size_t>(j)] += a[static_cast<std::size_t>(i * cols + j)] * x[static_cast<std::size_t>(i)];
}

/// The lift's displacement of dof i under d (0 without a lift).
double lifted(const ReducedLadderTables& t, std::size_t dof, const double d[3]) {
  return t.lift_rows.empty() ? 0.0 : dot(t.lift_rows.data() + 3 * dof, d, 3);
}

/// The indicator of reduced rung `rung` at q, as its own step measures it.
double ladder_envelope_ratio(const ReducedLadderTables& t, int rung, std::span<const double> q) {
  return detail::envelope_ratio(t.q_bound[static_cast<std::size_t>(rung)],
                                t.rungs[static_cast<std::size_t>(rung)].options().envelope_factor, q);
}

/// Puts (q, v, d) into reduced rung `rung`, its report describing that state.
void place(const ReducedLadderTables& t, ReducedLadderData& data, int rung, std::span<const double> q,
           std::span<const double> v, const double d[3]) {
  ReducedData& target = data.reduced[static_cast<std::size_t>(rung)];
  const auto r = static_cast<std::size_t>(size_of(t, rung));
  std::copy(q.begin(), q.begin() + static_cast<std::ptrdiff_t>(r), target.q.begin());
  std::copy(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(r), target.q_velocity.begin());
  std::copy(d, d + 3, target.prescribed_m);
  target.report = {};
  target.report.envelope_ratio = ladder_envelope_ratio(t, rung, target.q);
  target.report.out_of_envelope =
      target.report.envelope_ratio > t.rungs[static_cast<std::size_t>(rung)].options().envelope_factor;
}

/// Carries the state (q, v, d) of reduced rung `from` to the rung above: q_big = T q, v_big =
/// T v, or on the full order x = X + U q + L d, v = U q_dot.
void carry_up(const ReducedLadderTables& t, ReducedLadderData& data, int from, std::span<const double> q,
              std::span<const double> v, const double d[3]) {
  const int to = from + 1;
  if (is_reduced(t, to)) {
    const std::vector<double>& transfer = t.transfer[static_cast<std::size_t>(from)];
    const int rows = size_of(t, to), cols = size_of(t, from);
    multiply(transfer, rows, cols, q, data.projected_q);
    multiply(transfer, rows, cols, v, data.projected_velocity);
    place(t, data, to, data.projected_q, data.projected_velocity, d);
    return;
  }
  TetFemData& full = *data.full;
  const std::span<const double> rest = t.full->rest_positions_m();
  const int r = size_of(t, from);
  std::copy(d, d + 3, data.prescribed_m);
  for (std::size_t i = 0; i < full.positions_m.size(); ++i) {
    const double* row = t.top_rows.data() + i * static_cast<std::size_t>(r);
    full.positions_m[i] = rest[i] + dot(row, q.data(), r) + lifted(t, i, d);
    full.velocities_m_s[i] = dot(row, v.data(), r);
  }
}

/// The M-projection of the active rung's state onto the rung below, into data.projected_*;
/// returns |u - P u|_M / |u|_M of the displacement less the lift (0 at rest).
double project_down(const ReducedLadderTables& t, ReducedLadderData& data, int from) {
  const int lower = from - 1;
  const int r = size_of(t, lower);
  double total = 0.0;
  if (is_reduced(t, from)) {
    const ReducedData& source = data.reduced[static_cast<std::size_t>(from)];
    const std::vector<double>& transfer = t.transfer[static_cast<std::size_t>(lower)];
    multiply_transposed(transfer, size_of(t, from), r, source.q, data.projected_q);
    multiply_transposed(transfer, size_of(t, from), r, source.q_velocity, data.projected_velocity);
    total = dot(source.q.data(), source.q.data(), size_of(t, from));
  } else {
    const TetFemData& full = *data.full;
    const std::span<const double> rest = t.full->rest_positions_m();
    std::fill(data.projected_q.begin(), data.projected_q.begin() + r, 0.0);
    std::fill(data.projected_velocity.begin(), data.projected_velocity.begin() + r, 0.0);
    for (std::size_t i = 0; i < full.positions_m.size(); ++i) {
      const double mass = t.dof_mass_kg[i];
      const double u = full.positions_m[i] - rest[i] - lifted(t, i, data.prescribed_m);
      const double* row = t.top_rows.data() + i * static_cast<std::size_t>(r);
      total += mass * u * u;
      for (int j = 0; j < r; ++j) {
        data.projected_q[static_cast<std::size_t>(j)] += row[j] * mass * u;
        data.projected_velocity[static_cast<std::size_t>(j)] += row[j] * mass * full.velocities_m_s[i];
      }
    }
  }
  if (!(total > 0.0)) return 0.0;
  const double kept = dot(data.projected_q.data(), data.projected_q.data(), r);
  return std::sqrt(std::max(0.0, total - kept) / total);
}

/// Moves the ladder one rung down, to the projection of its state in data.projected_*.
void place_below(const ReducedLadderTables& t, ReducedLadderData& data) {
  const int from = data.active_rung;
  const double* d = is_reduced(t, from) ? data.reduced[static_cast<std::size_t>(from)].prescribed_m : data.prescribed_m;
  place(t, data, from - 1, data.projected_q, data.projected_velocity, d);
  --data.active_rung;
}

/// Steps rung `rung` with its flags cleared first; returns the flags the step raised.
HealthFlags step_rung(const ReducedLadderTables& t, ReducedLadderData& data, int rung, const TissueInputs& inputs) {
  if (!is_reduced(t, rung)) {
    data.full->health.clear_all();
    step(*t.full, *data.full, inputs);
    return data.full->health;
  }
  ReducedData& rung_data = data.reduced[static_cast<std::size_t>(rung)];
  rung_data.health.clear_all();
  step(t.rungs[static_cast<std::size_t>(rung)], rung_data, inputs);
  return rung_data.health;
}

/// The indicator of a step on a reduced rung (detail::reduced_indicator_fired).
bool indicator_fired(const ReducedLadderTables& t, int rung, HealthFlags raised) {
  return is_reduced(t, rung) && detail::reduced_indicator_fired(raised);
}

/// Counts the steps whose state fits the rung below and steps down when they are enough.
void consider_stepping_down(const ReducedLadderTables& t, ReducedLadderData& data) {
  const ReducedLadderOptions& o = t.options;
  const int from = data.active_rung;
  if (o.de_escalate_after_steps == 0 || from == 0) return;
  const double residual = project_down(t, data, from);
  const double ratio = ladder_envelope_ratio(t, from - 1, data.projected_q);
  data.report.projection_residual = residual;
  data.report.projected_envelope_ratio = ratio;
  const bool fits = ratio <= o.de_escalation_envelope_ratio && residual <= o.de_escalation_residual;
  data.inside_steps = fits ? data.inside_steps + 1 : 0;
  if (data.inside_steps < o.de_escalate_after_steps) return;
  place_below(t, data);
  data.inside_steps = 0;
  data.flagged_steps = 0;
  ++data.de_escalations;
  data.report.de_escalated = true;
}

/// Saves the state of reduced rung `rung` before its step.
void save_state(const ReducedLadderTables& t, ReducedLadderData& data, int rung) {
  const ReducedData& source = data.reduced[static_cast<std::size_t>(rung)];
  const auto r = static_cast<std::ptrdiff_t>(size_of(t, rung));
  std::copy(source.q.begin(), source.q.begin() + r, data.saved_q.begin());
  std::copy(source.q_velocity.begin(), source.q_velocity.begin() + r, data.saved_velocity.begin());
  std::copy(source.prescribed_m, source.prescribed_m + 3, data.saved_prescribed_m);
}

}  // namespace

double ReducedLadderModel::envelope_ratio(int rung, std::span<const double> q) const {
  return ladder_envelope_ratio(*tables_, rung, q);
}

void step(const ReducedLadderModel& model, ReducedLadderData& data, const TissueInputs& inputs) noexcept {
  const ReducedLadderTables& t = model.tables();
  const ReducedLadderOptions& o = t.options;
  const int rung = data.active_rung;
  data.report = {};
  data.report.rung = rung;
  if (is_reduced(t, rung)) save_state(t, data, rung);
  const HealthFlags raised = step_rung(t, data, rung, inputs);
  data.health.merge(raised);
  if (raised.has(HealthFlag::bad_sample)) return;  // refused, the state untouched
  std::copy(inputs.prescribed_displacement_m.begin(), inputs.prescribed_displacement_m.end(), data.prescribed_m);
  ++data.steps;
  const bool fired = indicator_fired(t, rung, raised);
  if (is_reduced(t, rung)) {
    const ReducedStepReport& stepped = data.reduced[static_cast<std::size_t>(rung)].report;
    data.report.envelope_ratio = stepped.envelope_ratio;
    data.report.estimated_error_m = stepped.estimated_error_m;
  }
  data.flagged_steps = fired ? data.flagged_steps + 1 : 0;
  const bool escalate =
      fired && o.escalation_allowed && rung + 1 < model.rung_count() && data.flagged_steps >= o.escalate_after_steps;
  if (!escalate) {
    consider_stepping_down(t, data);
    data.report.rung = data.active_rung;
    return;
  }
  carry_up(t, data, rung, data.saved_q, data.saved_velocity, data.saved_prescribed_m);
  data.active_rung = rung + 1;
  data.inside_steps = 0;
  ++data.escalations;
  const HealthFlags again = step_rung(t, data, rung + 1, inputs);
  data.flagged_steps = indicator_fired(t, rung + 1, again) ? 1 : 0;
  data.health.merge(again);
  data.health.raise(HealthFlag::reduced_escalated);
  data.report.escalated = true;
  data.report.rung = rung + 1;
}

void move_to_rung(const ReducedLadderModel& model, ReducedLadderData& data, int rung) noexcept {
  const ReducedLadderTables& t = model.tables();
  const int target = std::clamp(rung, 0, model.rung_count() - 1);
  while (data.active_rung < target) {
    const ReducedData& source = data.reduced[static_cast<std::size_t>(data.active_rung)];
    carry_up(t, data, data.active_rung, source.q, source.q_velocity, source.prescribed_m);
    ++data.active_rung;
  }
  while (data.active_rung > target) {
    project_down(t, data, data.active_rung);
    place_below(t, data);
  }
  data.flagged_steps = 0;
  data.inside_steps = 0;
  data.report.rung = data.active_rung;
}

void reconstruct_displacements_m(const ReducedLadderModel& model, const ReducedLadderData& data,
                                 std::span<const std::int32_t> nodes, std::span<double> out_xyz) noexcept {
  const ReducedLadderTables& t = model.tables();
  if (is_reduced(t, data.active_rung)) {
    const auto rung = static_cast<std::size_t>(data.active_rung);
    reconstruct_displacements_m(t.rungs[rung], data.reduced[rung], nodes, out_xyz);
    return;
  }
  const std::span<const double> rest = t.full->rest_positions_m();
  const std::size_t count = std::min(nodes.size(), out_xyz.size() / 3);
  for (std::size_t k = 0; k < count; ++k) {
    const bool valid = nodes[k] >= 0 && nodes[k] < t.node_count;
    const auto base = 3 * static_cast<std::size_t>(valid ? nodes[k] : 0);
    for (std::size_t c = 0; c < 3; ++c)
      out_xyz[3 * k + c] = valid ? data.full->positions_m[base + c] - rest[base + c] : 0.0;
  }
}

void reconstruct_all_displacements_m(const ReducedLadderModel& model, const ReducedLadderData& data,
                                     std::span<double> out) noexcept {
  const ReducedLadderTables& t = model.tables();
  if (is_reduced(t, data.active_rung)) {
    const auto rung = static_cast<std::size_t>(data.active_rung);
    reconstruct_all_displacements_m(t.rungs[rung], data.reduced[rung], out);
    return;
  }
  const std::span<const double> rest = t.full->rest_positions_m();
  const std::size_t values = std::min(out.size(), rest.size());
  for (std::size_t i = 0; i < values; ++i) out[i] = data.full->positions_m[i] - rest[i];
}

}  // namespace nav
