#pragma once
// The tick and the data of a coupled needle, shared by the full-order and the reduced
// couplings (instantiated in tissue_coupling.cpp and reduced_coupling.cpp) and by the
// operating loop, which schedules step_needle() and step_tissue() itself. Each tissue
// supplies refresh_displacements() below.
#include <algorithm>
#include <cmath>

#include "nav/needle/coupled_needle.hpp"

namespace nav {

class TetFemModel;
struct TetFemData;
class ReducedModel;
struct ReducedData;

namespace detail {

/// The coupling's own checks (a layer, positive counts); the Error names the field.
Status validate_coupling(const NeedleTissueScene& scene, std::size_t max_point_forces,
                         int needle_steps_per_tissue_step);

/// Refreshes data.displacements_m from data.free_tissue after a tissue step (all nodes, or those
/// it needs, the surfaces' vertices within the needle's reach among them).
void refresh_displacements(const CoupledNeedleModelOf<TetFemModel>& model,
                           CoupledNeedleDataOf<TetFemData>& data) noexcept;
void refresh_displacements(const CoupledNeedleModelOf<ReducedModel>& model,
                           CoupledNeedleDataOf<ReducedData>& data) noexcept;

/// Merges the rows' forces (opposite on the tissue) per tissue node into `out`; beyond
/// `max_forces` distinct nodes keeps the largest (stable order) and returns how many were
/// dropped in `dropped`. Returns the count kept.
std::size_t gather_point_forces(const NeedleTissueData& interaction, std::span<PointForce> out, std::size_t max_forces,
                                int& dropped) noexcept;

/// The coupled data around made interaction and tissue data (the tissue's and its free
/// motion's), with the displacement and point force buffers and `refreshed_nodes` slots for
/// on-demand refreshes.
template <class TissueModel, class TissueData>
Result<CoupledNeedleDataOf<TissueData>> make_coupled_data(const CoupledNeedleModelOf<TissueModel>& model,
                                                          const NeedlePose& base, Result<TissueData> tissue,
                                                          Result<TissueData> free_tissue, std::size_t node_count,
                                                          std::size_t refreshed_nodes) {
  auto interaction = make_needle_tissue_data(model.interaction, base);
  if (!interaction.ok()) return interaction.error();
  if (!tissue.ok()) return tissue.error();
  if (!free_tissue.ok()) return free_tissue.error();
  const std::size_t values = 3 * node_count;
  // One point force per row at most, before merging and capping, then the tissue's others.
  const std::size_t forces = static_cast<std::size_t>(model.interaction.slot_count()) + model.other_point_forces;
  ArenaPlan plan;
  plan.add<double>(values).add<PointForce>(forces).add<std::int32_t>(refreshed_nodes).add<double>(3 * refreshed_nodes);
  CoupledNeedleDataOf<TissueData> data(Arena("coupled_needle_data", plan.bytes()), std::move(interaction).value(),
                                       std::move(tissue).value(), std::move(free_tissue).value());
  auto displacements = data.arena.template allocate<double>("tissue displacements", values);
  auto point_forces = data.arena.template allocate<PointForce>("point forces", forces);
  auto nodes = data.arena.template allocate<std::int32_t>("refreshed nodes", refreshed_nodes);
  auto refreshed = data.arena.template allocate<double>("refreshed displacements", 3 * refreshed_nodes);
  if (!displacements.ok()) return displacements.error();
  if (!point_forces.ok()) return point_forces.error();
  if (!nodes.ok()) return nodes.error();
  if (!refreshed.ok()) return refreshed.error();
  data.displacements_m = displacements.value();
  data.point_forces = point_forces.value();
  data.refreshed_nodes = nodes.value();
  data.refreshed_displacements_m = refreshed.value();
  return data;
}

}  // namespace detail

template <class TissueModel, class TissueData>
void step_needle(const CoupledNeedleModelOf<TissueModel>& model, CoupledNeedleDataOf<TissueData>& data,
                 const NeedleInputs& inputs) noexcept {
  NeedleTissueInputs needle_inputs;
  needle_inputs.needle = inputs;
  needle_inputs.tissue_displacements_m = data.displacements_m;
  step(model.interaction, data.interaction, needle_inputs);
}

template <class TissueModel, class TissueData>
void step_tissue(const CoupledNeedleModelOf<TissueModel>& model, CoupledNeedleDataOf<TissueData>& data,
                 TissueInputs tissue_inputs) noexcept {
  NeedleTissueData& interaction = data.interaction;
  data.point_force_count =
      detail::gather_point_forces(interaction, data.point_forces, model.max_point_forces, data.dropped_point_forces);
  if (data.dropped_point_forces > 0) interaction.health.raise(HealthFlag::pool_full);
  const std::size_t others = std::min(tissue_inputs.point_forces.size(), model.other_point_forces);
  std::copy_n(tissue_inputs.point_forces.begin(), others, data.point_forces.begin() + data.point_force_count);
  data.point_force_count += others;
  tissue_inputs.point_forces = std::span<const PointForce>(data.point_forces.data(), data.point_force_count);
  step(*model.tissue, data.tissue, tissue_inputs);
  // The tissue now carries this tick's forces; its free motion under them is what the
  // constraints meet until its next step.
  std::copy(interaction.slot_forces.begin(), interaction.slot_forces.end(), interaction.applied_forces.begin());
  copy_state(data.tissue, data.free_tissue);
  step(*model.tissue, data.free_tissue, tissue_inputs);
  detail::refresh_displacements(model, data);
  refresh_surfaces(model.interaction, interaction, data.displacements_m);
}

template <class TissueModel, class TissueData>
void step(const CoupledNeedleModelOf<TissueModel>& model, CoupledNeedleDataOf<TissueData>& data,
          const NeedleInputs& inputs) noexcept {
  step_needle(model, data, inputs);
  if (++data.ticks % model.needle_steps_per_tissue_step == 0) step_tissue(model, data, TissueInputs{});
  data.interaction.health.merge(data.tissue.health);
}

}  // namespace nav
