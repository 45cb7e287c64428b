#include "nav/needle/tissue_coupling.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

namespace nav {

namespace {

std::int32_t nearest_node(std::span<const double> rest_m, const Point3& point_m) {
  std::int32_t best = 0;
  double best_m2 = -1.0;
  for (std::size_t n = 0; n < rest_m.size() / 3; ++n) {
    double d2 = 0.0;
    for (int c = 0; c < 3; ++c) d2 += (rest_m[3 * n + c] - point_m[c]) * (rest_m[3 * n + c] - point_m[c]);
    if (best_m2 < 0.0 || d2 < best_m2) {
      best_m2 = d2;
      best = static_cast<std::int32_t>(n);
    }
  }
  return best;
}

/// Adds `force` on `node` to the list, merging with an entry for the same node.
void add_point_force(std::span<PointForce> forces, std::size_t& count, std::int32_t node, const Eigen::Vector3d& force) {
  for (std::size_t k = 0; k < count; ++k)
    if (forces[k].node == node) {
      for (int c = 0; c < 3; ++c) forces[k].force_n[c] += force[c];
      return;
    }
  forces[count++] = PointForce{node, {force[0], force[1], force[2]}};
}

/// Steps the tissue with the interaction's current forces (opposite on the tissue), then
/// records them as carried and refreshes the displacements.
void step_tissue(const CoupledNeedleModel& model, CoupledNeedleData& data) {
  NeedleTissueData& interaction = data.interaction;
  std::size_t count = 0;
  for (int r = 0; r < interaction.row_count; ++r) {
    const ConstraintRow& row = interaction.rows[static_cast<std::size_t>(r)];
    if (row.tissue_node < 0) continue;
    add_point_force(data.point_forces, count, row.tissue_node, -interaction.row_forces[static_cast<std::size_t>(r)] * row.direction);
  }
  data.dropped_point_forces = 0;
  if (count > model.max_point_forces) {
    // Keep the largest: a stable order by magnitude, then by node.
    std::sort(data.point_forces.begin(), data.point_forces.begin() + static_cast<std::ptrdiff_t>(count),
              [](const PointForce& a, const PointForce& b) {
                const double na = std::hypot(a.force_n[0], a.force_n[1], a.force_n[2]);
                const double nb = std::hypot(b.force_n[0], b.force_n[1], b.force_n[2]);
                return na != nb ? na > nb : a.node < b.node;
              });
    data.dropped_point_forces = static_cast<int>(count - model.max_point_forces);
    count = model.max_point_forces;
    interaction.health.raise(HealthFlag::pool_full);
  }
  TissueInputs inputs;
  inputs.point_forces = std::span<const PointForce>(data.point_forces.data(), count);
  step(*model.tissue, data.tissue, inputs);
  std::copy(interaction.slot_forces.begin(), interaction.slot_forces.end(), interaction.applied_forces.begin());
  const std::span<const double> rest = model.tissue->rest_positions_m();
  for (std::size_t i = 0; i < data.displacements_m.size(); ++i) data.displacements_m[i] = data.tissue.positions_m[i] - rest[i];
}

}  // namespace

Result<ProbedCompliance> probe_tet_fem_compliance(const TetFemModel& tissue, const Point3& point_m, double probe_force_n) {
  if (!(std::isfinite(probe_force_n) && probe_force_n > 0.0)) return Error{"must be positive", "", 0, "probe_force_n"};
  const std::span<const double> rest = tissue.rest_positions_m();
  const std::int32_t node = nearest_node(rest, point_m);
  const std::size_t nodes = rest.size() / 3;
  std::vector<double> response(nodes, 0.0);  // displacement magnitude per node, summed over the 3 probes
  double columns[9] = {};  // the node's displacement per newton, one column per probe axis
  for (int axis = 0; axis < 3; ++axis) {
    auto data = make_tet_fem_data(tissue);
    if (!data.ok()) return data.error();
    PointForce force{node, {0.0, 0.0, 0.0}};
    force.force_n[static_cast<std::size_t>(axis)] = probe_force_n;
    TissueInputs inputs;
    inputs.point_forces = std::span<const PointForce>(&force, 1);
    step(tissue, data.value(), inputs);
    if (!data.value().health.healthy()) return Error{"the tissue refused the probe step", "", 0, "tissue"};
    for (std::size_t n = 0; n < nodes; ++n) {
      double d2 = 0.0;
      for (int c = 0; c < 3; ++c) d2 += std::pow(data.value().positions_m[3 * n + c] - rest[3 * n + c], 2);
      response[n] += std::sqrt(d2);
    }
    for (int c = 0; c < 3; ++c)
      columns[3 * axis + c] = (data.value().positions_m[3 * static_cast<std::size_t>(node) + static_cast<std::size_t>(c)] -
                               rest[3 * static_cast<std::size_t>(node) + static_cast<std::size_t>(c)]) / probe_force_n;
  }
  ProbedCompliance probed;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) probed.tensor_m_per_n[static_cast<std::size_t>(3 * j + i)] = 0.5 * (columns[3 * j + i] + columns[3 * i + j]);
  probed.point_compliance_m_per_n = (columns[0] + columns[4] + columns[8]) / 3.0;
  if (!(probed.point_compliance_m_per_n > 0.0)) return Error{"no positive compliance at the probed node", "", 0, "tissue"};
  // Gaussian fit of the near-field decay: ratio r at distance d gives l = d / sqrt(-2 ln r);
  // the median over the 12 nearest nodes (the far field is not Gaussian).
  std::vector<std::pair<double, double>> near;  // (distance, response ratio)
  const double self_response = response[static_cast<std::size_t>(node)];
  for (std::size_t n = 0; n < nodes; ++n) {
    if (n == static_cast<std::size_t>(node)) continue;
    double d2 = 0.0;
    for (int c = 0; c < 3; ++c) d2 += std::pow(rest[3 * n + c] - rest[3 * static_cast<std::size_t>(node) + c], 2);
    near.emplace_back(std::sqrt(d2), response[n] / self_response);
  }
  std::sort(near.begin(), near.end());
  std::vector<double> lengths;
  for (std::size_t k = 0; k < std::min<std::size_t>(12, near.size()); ++k)
    if (near[k].second > 0.0 && near[k].second < 1.0) lengths.push_back(near[k].first / std::sqrt(-2.0 * std::log(near[k].second)));
  if (lengths.empty()) return Error{"the probe's response does not decay over the mesh", "", 0, "tissue"};
  std::nth_element(lengths.begin(), lengths.begin() + static_cast<std::ptrdiff_t>(lengths.size() / 2), lengths.end());
  probed.correlation_length_m = lengths[lengths.size() / 2];
  return probed;
}

Result<CoupledNeedleModel> make_coupled_needle_model(const NeedleParameters& needle, const NeedleTissueScene& scene,
                                                     const TetFemModel& tissue, std::size_t max_point_forces,
                                                     int needle_steps_per_tissue_step) {
  if (scene.layers.empty()) return Error{"the coupled scene needs a layer", "", 0, "scene.layers"};
  if (needle_steps_per_tissue_step < 1) return Error{"must be at least 1", "", 0, "needle_steps_per_tissue_step"};
  if (max_point_forces < 1) return Error{"must be at least 1", "", 0, "max_point_forces"};
  const auto probed = probe_tet_fem_compliance(tissue, scene.layers.front().surface_point_m, 0.01);
  if (!probed.ok()) return probed.error();
  NeedleTissueScene coupled = scene;
  coupled.point_compliance_m_per_n = probed.value().point_compliance_m_per_n;
  coupled.compliance_correlation_length_m = probed.value().correlation_length_m;
  auto interaction = make_needle_tissue_model(needle, coupled, tissue.rest_positions_m());
  if (!interaction.ok()) return interaction.error();
  interaction.value().compliance_tensor_m_per_n = Eigen::Map<const Eigen::Matrix3d>(probed.value().tensor_m_per_n.data());
  return CoupledNeedleModel{std::move(interaction).value(), &tissue, needle_steps_per_tissue_step, max_point_forces};
}

Result<CoupledNeedleData> make_coupled_needle_data(const CoupledNeedleModel& model, const NeedlePose& base) {
  auto interaction = make_needle_tissue_data(model.interaction, base);
  if (!interaction.ok()) return interaction.error();
  auto tissue = make_tet_fem_data(*model.tissue);
  if (!tissue.ok()) return tissue.error();
  const std::size_t values = model.tissue->rest_positions_m().size();
  // One point force per row at most, before merging and capping.
  const auto forces = static_cast<std::size_t>(model.interaction.slot_count());
  ArenaPlan plan;
  plan.add<double>(values).add<PointForce>(forces);
  CoupledNeedleData data(Arena("coupled_needle_data", plan.bytes()), std::move(interaction).value(), std::move(tissue).value());
  auto displacements = data.arena.allocate<double>("tissue displacements", values);
  auto point_forces = data.arena.allocate<PointForce>("point forces", forces);
  if (!displacements.ok()) return displacements.error();
  if (!point_forces.ok()) return point_forces.error();
  data.displacements_m = displacements.value();
  data.point_forces = point_forces.value();
  return data;
}

void step(const CoupledNeedleModel& model, CoupledNeedleData& data, const NeedleInputs& inputs) noexcept {
  NeedleTissueInputs needle_inputs;
  needle_inputs.needle = inputs;
  needle_inputs.tissue_displacements_m = data.displacements_m;
  step(model.interaction, data.interaction, needle_inputs);
  if (++data.ticks % model.needle_steps_per_tissue_step == 0) step_tissue(model, data);
  data.interaction.health.merge(data.tissue.health);
}

}  // namespace nav
