#include "nav/needle/tissue_coupling.hpp"

#include <algorithm>
#include <cmath>
#include <vector>

#include "nav/needle/coupled_needle_step.hpp"

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

}  // namespace

Result<ProbedCompliance> probe_tet_fem_compliance(const TetFemModel& tissue, const Point3& point_m,
                                                  double probe_force_n) {
  if (!(std::isfinite(probe_force_n) && probe_force_n > 0.0))
    return Error{.message = "must be positive", .field = "probe_force_n"};
  const std::span<const double> rest = tissue.rest_positions_m();
  const std::int32_t node = nearest_node(rest, point_m);
  const std::size_t nodes = rest.size() / 3;
  std::vector<double> response(nodes, 0.0);  // displacement magnitude per node, summed over the 3 probes
  std::vector<double> moved_m(3 * nodes);    // the nodes' points' displacements (point_displacements_m)
  double columns[9] = {};                    // the node's displacement per newton, one column per probe axis
  for (int axis = 0; axis < 3; ++axis) {
    auto data = make_tet_fem_data(tissue);
    if (!data.ok()) return data.error();
    PointForce force{node, {0.0, 0.0, 0.0}};
    force.force_n[static_cast<std::size_t>(axis)] = probe_force_n;
    TissueInputs inputs;
    inputs.point_forces = std::span<const PointForce>(&force, 1);
    step(tissue, data.value(), inputs);
    if (!data.value().health.healthy()) return Error{.message = "the tissue refused the probe step", .field = "tissue"};
    point_displacements_m(tissue, data.value(), moved_m);
    for (std::size_t n = 0; n < nodes; ++n)
      response[n] +=
          std::sqrt(std::pow(moved_m[3 * n], 2) + std::pow(moved_m[3 * n + 1], 2) + std::pow(moved_m[3 * n + 2], 2));
    for (int c = 0; c < 3; ++c)
      columns[3 * axis + c] = moved_m[3 * static_cast<std::size_t>(node) + static_cast<std::size_t>(c)] / probe_force_n;
  }
  ProbedCompliance probed;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      probed.tensor_m_per_n[static_cast<std::size_t>(3 * j + i)] = 0.5 * (columns[3 * j + i] + columns[3 * i + j]);
  probed.point_compliance_m_per_n = (columns[0] + columns[4] + columns[8]) / 3.0;
  if (!(probed.point_compliance_m_per_n > 0.0))
    return Error{.message = "no positive compliance at the probed node", .field = "tissue"};
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
    if (near[k].second > 0.0 && near[k].second < 1.0)
      lengths.push_back(near[k].first / std::sqrt(-2.0 * std::log(near[k].second)));
  if (lengths.empty()) return Error{.message = "the probe's response does not decay over the mesh", .field = "tissue"};
  std::nth_element(lengths.begin(), lengths.begin() + static_cast<std::ptrdiff_t>(lengths.size() / 2), lengths.end());
  probed.correlation_length_m = lengths[lengths.size() / 2];
  return probed;
}

Result<CoupledNeedleModel> make_coupled_needle_model(const NeedleParameters& needle, const NeedleTissueScene& scene,
                                                     const TetFemModel& tissue, std::size_t max_point_forces,
                                                     int needle_steps_per_tissue_step) {
  if (auto valid = detail::validate_coupling(scene, max_point_forces, needle_steps_per_tissue_step); !valid)
    return valid.error();
  if (has_rest_step_response(tissue)) {
    // The tissue's own response at the constraint points' nodes, solved as they come.
    auto interaction = make_needle_tissue_model(needle, scene, tissue.rest_positions_m());
    if (!interaction.ok()) return interaction.error();
    interaction.value().node_response_source = &tissue;
    return CoupledNeedleModel{std::move(interaction).value(), &tissue, needle_steps_per_tissue_step, max_point_forces};
  }
  const auto probed = probe_tet_fem_compliance(tissue, scene.layers.front().surface_point_m, 0.01);
  if (!probed.ok()) return probed.error();
  NeedleTissueScene coupled = scene;
  coupled.point_compliance_m_per_n = probed.value().point_compliance_m_per_n;
  coupled.compliance_correlation_length_m = probed.value().correlation_length_m;
  auto interaction = make_needle_tissue_model(needle, coupled, tissue.rest_positions_m());
  if (!interaction.ok()) return interaction.error();
  interaction.value().compliance_tensor_m_per_n =
      Eigen::Map<const Eigen::Matrix3d>(probed.value().tensor_m_per_n.data());
  return CoupledNeedleModel{std::move(interaction).value(), &tissue, needle_steps_per_tissue_step, max_point_forces};
}

Result<CoupledNeedleData> make_coupled_needle_data(const CoupledNeedleModel& model, const NeedlePose& base) {
  return detail::make_coupled_data(model, base, make_tet_fem_data(*model.tissue), make_tet_fem_data(*model.tissue),
                                   model.tissue->rest_positions_m().size() / 3, 0);
}

namespace detail {

void refresh_displacements(const CoupledNeedleModel& model, CoupledNeedleData& data) noexcept {
  point_displacements_m(*model.tissue, data.free_tissue, data.displacements_m);
}

}  // namespace detail

template void step(const CoupledNeedleModel&, CoupledNeedleData&, const NeedleInputs&) noexcept;

}  // namespace nav
