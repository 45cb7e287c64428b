#include <algorithm>
#include <cmath>

#include "nav/needle/gauss_seidel.hpp"
#include "nav/needle/needle_step.hpp"
#include "nav/needle/needle_tissue_model.hpp"
#include "nav/needle/needle_tissue_rows.hpp"
#include "nav/needle/tissue_points.hpp"

namespace nav {
namespace {

using detail::compliant_displacement_m;

/// The tissue material point now at `position_m` (after this step's forces).
TissuePoint point_now_at(const NeedleTissueModel& model, const NeedleTissueData& data,
                         const Eigen::Vector3d& position_m, std::span<const double> displacements_m) {
  // The low-rank compliance needs the carrying node: the one nearest the point now.
  const std::int32_t node = model.compliance_rank > 0 ? tissue_point_at(model, position_m, displacements_m).node : -1;
  return tissue_point_at(model, position_m - compliant_displacement_m(model, data, position_m, node), displacements_m);
}

/// Where a tissue point is after this step's forces.
Eigen::Vector3d position_after(const NeedleTissueModel& model, const NeedleTissueData& data, const TissuePoint& point,
                               std::span<const double> displacements_m) {
  const Eigen::Vector3d before = tissue_point_position_m(point, displacements_m);
  return before + compliant_displacement_m(model, data, before, point.node);
}

void apply_correction(const NeedleTissueModel& model, NeedleTissueData& data) {
  std::fill(data.nodal_forces.begin(), data.nodal_forces.end(), 0.0);
  for (int r = 0; r < data.row_count; ++r) {
    const ConstraintRow& row = data.rows[static_cast<std::size_t>(r)];
    const Eigen::Vector3d force = data.row_forces[static_cast<std::size_t>(r)] * row.direction;
    for (int k = 0; k < 2; ++k) {
      const double w = k == 0 ? 1.0 - row.weight : row.weight;
      if (w == 0.0) continue;
      Eigen::Map<Eigen::Vector3d>(data.nodal_forces.data() + 6 * static_cast<std::size_t>(row.node + k)) += w * force;
    }
  }
  apply_needle_correction(model.needle, data.needle, data.nodal_forces);
}

/// Insertion force along the base axis and its parts, from the rows' forces.
InsertionForces insertion_forces(const NeedleTissueModel& model, const NeedleTissueData& data) {
  const Eigen::Vector3d axis = node_rotation(data.needle.rotations_wxyz, 0) * Eigen::Vector3d::UnitX();
  InsertionForces f;
  for (int r = 0; r < data.row_count; ++r) {
    const ConstraintRow& row = data.rows[static_cast<std::size_t>(r)];
    const double resisting = -data.row_forces[static_cast<std::size_t>(r)] * row.direction.dot(axis);
    f.total_n += resisting;
    if (row.slot < model.tip_slot())
      f.stiffness_n += resisting;
    else if (row.slot < model.path_slot(0))
      f.cutting_n += resisting;
    else
      f.friction_n += resisting;
  }
  return f;
}

/// Frees slots: no force, and none counted as carried by the tissue (a force the tissue
/// model still holds from a freed slot is corrected at its next step).
void zero_slots(NeedleTissueData& data, int first_slot, int count) {
  std::fill_n(data.slot_forces.begin() + first_slot, count, 0.0);
  std::fill_n(data.applied_forces.begin() + first_slot, count, 0.0);
}

/// Puncture, release and surface slip of the touching layers.
void update_layers(const NeedleTissueModel& model, NeedleTissueData& data, std::span<const double> displacements_m) {
  const Eigen::Vector3d tip = needle_tip_m(data.needle);
  for (int l = 0; l < model.layer_count(); ++l) {
    LayerState& layer = data.layers[static_cast<std::size_t>(l)];
    if (layer.phase != LayerPhase::touching) continue;
    const TissueLayer& spec = model.scene.layers[static_cast<std::size_t>(l)];
    const double normal_n = data.slot_forces[static_cast<std::size_t>(3 * l)];
    const Eigen::Vector3d contact = position_after(model, data, layer.contact, displacements_m);
    const Eigen::Vector3d& n = layer.contact_normal;
    if (normal_n >= spec.puncture_force_n * (1.0 - kForceAtBoundSlack)) {
      layer.phase = LayerPhase::punctured;
      layer.holed = true;
      layer.hole = layer.contact;
      layer.cut_front = point_now_at(model, data, tip, displacements_m);
      ++data.report.punctures;
      zero_slots(data, 3 * l, 3);
      continue;
    }
    if (normal_n <= 0.0 && n.dot(tip - contact) > 0.0) {
      layer.phase = LayerPhase::outside;
      zero_slots(data, 3 * l, 3);
      continue;
    }
    const double tangential_n = std::hypot(data.slot_forces[static_cast<std::size_t>(3 * l + 1)],
                                           data.slot_forces[static_cast<std::size_t>(3 * l + 2)]);
    if (normal_n > 0.0 && tangential_n >= spec.surface_friction_coefficient * normal_n * (1.0 - 1e-6)) {
      const Eigen::Vector3d slip = tip - contact;
      layer.contact.rest_m += slip - n.dot(slip) * n;  // the tip slid: it now touches another point
    }
  }
}

/// Cut front, tip anchor, path slip, removal and creation.
void update_path(const NeedleTissueModel& model, NeedleTissueData& data, std::span<const double> displacements_m) {
  const Eigen::Vector3d tip = needle_tip_m(data.needle);
  const int cut = detail::cutting_layer(model, data, tip, displacements_m);
  const double length_m = model.needle.parameters.length_m;
  data.tip_anchor = point_now_at(model, data, tip, displacements_m);
  if (cut < 0) {
    zero_slots(data, model.tip_slot(), 1);
  } else {
    const TissueLayer& spec = model.scene.layers[static_cast<std::size_t>(cut)];
    // A cut at its force advances the front to the tissue point at the tip.
    if (data.slot_forces[static_cast<std::size_t>(model.tip_slot())] >=
        spec.cutting_force_n * (1.0 - kForceAtBoundSlack))
      data.layers[static_cast<std::size_t>(cut)].cut_front = data.tip_anchor;
  }
  // Slip: a tissue point at its friction bound now faces another material point of the
  // needle, shifted by the axial gap left after the correction.
  const std::span<const ConstraintRow> rows(data.rows.data(), static_cast<std::size_t>(data.row_count));
  for (std::size_t r = 0; r < rows.size(); ++r) {
    if (rows[r].law != RowLaw::friction_axial) continue;
    const double limit_n = row_limit_n(rows, r, data.row_forces);
    if (std::abs(data.row_forces[r]) >= limit_n * (1.0 - kForceAtBoundSlack))
      data.path[static_cast<std::size_t>((rows[r].slot - model.path_slot(0)) / 3)].arclength_m -= data.row_gaps[r];
  }
  double newest_m = -1.0;
  for (int p = 0; p < model.scene.max_path_points; ++p) {
    PathPoint& point = data.path[static_cast<std::size_t>(p)];
    if (!point.active) continue;
    if (point.arclength_m > length_m || point.arclength_m < 0.0) {
      point.active = false;
      zero_slots(data, model.path_slot(p), 3);
      continue;
    }
    newest_m = std::max(newest_m, point.arclength_m);
  }
  // A new point at the tip once the newest is a spacing behind it (the first at once).
  if (cut < 0 || (newest_m >= 0.0 && length_m - newest_m < model.scene.path_spacing_m)) return;
  for (int p = 0; p < model.scene.max_path_points; ++p) {
    PathPoint& point = data.path[static_cast<std::size_t>(p)];
    if (point.active) continue;
    point = PathPoint{true, length_m, data.tip_anchor, cut};
    zero_slots(data, model.path_slot(p), 3);
    return;
  }
  ++data.report.lost_path_points;
  data.health.raise(HealthFlag::pool_full);
}

}  // namespace

void step(const NeedleTissueModel& model, NeedleTissueData& data, const NeedleTissueInputs& inputs) noexcept {
  if (!accept_base_pose(model.needle, data.needle, inputs.needle.base)) {
    data.health.merge(data.needle.health);
    return;
  }
  NeedleInputs needle_inputs = inputs.needle;
  const Eigen::Vector3d bevel_n = detail::bevel_force_n(model, data);
  for (int c = 0; c < 3; ++c) needle_inputs.tip_force_n[static_cast<std::size_t>(c)] += bevel_n[c];
  if (!needle_free_motion(model.needle, data.needle, needle_inputs)) {
    data.health.merge(data.needle.health);
    return;
  }
  const std::span<const double> u = inputs.tissue_displacements_m;
  detail::build_rows(model, data, u);
  detail::assemble_compliance(model, data);
  const auto m = static_cast<std::size_t>(data.row_count);
  data.report.residual_m =
      solve_gauss_seidel(std::span<const ConstraintRow>(data.rows.data(), m),
                         std::span<const double>(data.compliance.data(), m * data.compliance_stride),
                         data.compliance_stride, model.scene.gauss_seidel_sweeps, data.row_forces.first(m),
                         data.row_gaps.first(m), GaussSeidelWorkspace{data.sweep_rows, model.lane_kernels});
  const bool finite = std::all_of(data.row_forces.begin(), data.row_forces.begin() + static_cast<std::ptrdiff_t>(m),
                                  [](double f) { return std::isfinite(f); });
  if (!finite) {
    std::fill(data.row_forces.begin(), data.row_forces.end(), 0.0);
    std::fill(data.slot_forces.begin(), data.slot_forces.end(), 0.0);
    data.health.raise(HealthFlag::non_finite_state);
    data.row_count = 0;
    data.point_count = 0;
  }
  if (data.report.residual_m > model.scene.residual_bound_m) data.health.raise(HealthFlag::solver_not_converged);
  for (std::size_t r = 0; r < static_cast<std::size_t>(data.row_count); ++r)
    data.slot_forces[static_cast<std::size_t>(data.rows[r].slot)] = data.row_forces[r];
  apply_correction(model, data);
  data.report.forces = insertion_forces(model, data);
  data.report.contact_force_n = 0.0;
  for (int l = 0; l < model.layer_count(); ++l)
    if (data.layers[static_cast<std::size_t>(l)].phase == LayerPhase::touching)
      data.report.contact_force_n =
          std::max(data.report.contact_force_n, data.slot_forces[static_cast<std::size_t>(3 * l)]);
  data.report.active_rows = data.row_count;
  if (model.layer_count() > 0)
    data.report.tip_depth_m = -detail::layer_hit(model, data, 0, needle_tip_m(data.needle), u).distance_m;
  update_layers(model, data, u);
  update_path(model, data, u);
  data.report.active_path_points =
      static_cast<int>(std::count_if(data.path.begin(), data.path.end(), [](const PathPoint& p) { return p.active; }));
  data.health.merge(data.needle.health);
  ++data.steps;
}

Eigen::Vector3d tip_force_n(const NeedleTissueModel& model, const NeedleTissueData& data) noexcept {
  Eigen::Vector3d force = Eigen::Vector3d::Zero();
  for (int r = 0; r < data.row_count; ++r) {
    const ConstraintRow& row = data.rows[static_cast<std::size_t>(r)];
    if (row.slot <= model.tip_slot()) force += data.row_forces[static_cast<std::size_t>(r)] * row.direction;
  }
  return force;
}

}  // namespace nav
