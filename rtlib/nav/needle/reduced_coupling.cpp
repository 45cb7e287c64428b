#include "nav/needle/reduced_coupling.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

#include "nav/needle/coupled_needle_step.hpp"

namespace nav {

namespace {

/// Nodes refreshed round-robin at each tissue step, besides those the interaction refers to.
constexpr std::int64_t kRefreshBlockNodes = 64;

/// Slots of refreshed nodes: four per layer (surface, contact, hole, cut front), one per
/// path point, the tip anchor, the round-robin block and every surface vertex.
std::size_t refresh_capacity(const NeedleTissueModel& model) {
  std::size_t surface_vertices = 0;
  for (const detail::SurfaceBvh& bvh : model.surface_bvhs) surface_vertices += bvh.vertex_nodes.size();
  return static_cast<std::size_t>(4 * model.layer_count() + model.scene.max_path_points + 1 + kRefreshBlockNodes) +
         surface_vertices;
}

/// q after one step from rest under `force` (none: no load).
Result<Eigen::VectorXd> one_step_q(const ReducedModel& tissue, const PointForce* force) {
  auto data = make_reduced_data(tissue);
  if (!data.ok()) return data.error();
  TissueInputs inputs;
  if (force != nullptr) inputs.point_forces = std::span<const PointForce>(force, 1);
  step(tissue, data.value(), inputs);
  if (data.value().health.has(HealthFlag::bad_sample) || data.value().health.has(HealthFlag::non_finite_state))
    return Error{.message = "the reduced model refused the probe step", .field = "tissue"};
  return Eigen::VectorXd(
      Eigen::Map<const Eigen::VectorXd>(data.value().q.data(), static_cast<Eigen::Index>(data.value().q.size())));
}

}  // namespace

Result<ReducedComplianceFactors> reduced_compliance_factors(const ReducedModel& tissue, double probe_force_n) {
  if (!(std::isfinite(probe_force_n) && probe_force_n > 0.0))
    return Error{.message = "must be positive", .field = "probe_force_n"};
  const int r = tissue.basis_size();
  if (r < 1 || r > kMaxComplianceRank) return Error{.message = "must be within [1, 256]", .field = "tissue.basis_size"};
  const auto n3 = static_cast<Eigen::Index>(3 * tissue.node_count());
  // U, column by column: the displacements of a unit coordinate.
  auto scratch = make_reduced_data(tissue);
  if (!scratch.ok()) return scratch.error();
  Eigen::MatrixXd basis(n3, r);
  std::vector<double> column(static_cast<std::size_t>(n3));
  for (int j = 0; j < r; ++j) {
    std::fill(scratch.value().q.begin(), scratch.value().q.end(), 0.0);
    scratch.value().q[static_cast<std::size_t>(j)] = 1.0;
    reconstruct_all_displacements_m(tissue, scratch.value(), column);
    basis.col(j) = Eigen::Map<const Eigen::VectorXd>(column.data(), n3);
  }
  // r node axes whose basis rows are well conditioned, probed one by one: their generalized
  // forces F (columns U_k^T) and the changes of q per newton D give G = D F^-1.
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> pivoting(basis.transpose());
  if (pivoting.rank() < r) return Error{.message = "the basis has dependent columns", .field = "tissue.basis"};
  const auto rest_q = one_step_q(tissue, nullptr);
  if (!rest_q.ok()) return rest_q.error();
  Eigen::MatrixXd forces(r, r), changes(r, r);
  for (int k = 0; k < r; ++k) {
    const Eigen::Index dof = pivoting.colsPermutation().indices()(k);
    PointForce probe{static_cast<std::int32_t>(dof / 3), {0.0, 0.0, 0.0}};
    probe.force_n[static_cast<std::size_t>(dof % 3)] = probe_force_n;
    const auto q = one_step_q(tissue, &probe);
    if (!q.ok()) return q.error();
    forces.col(k) = basis.row(dof).transpose();
    changes.col(k) = (q.value() - rest_q.value()) / probe_force_n;
  }
  const Eigen::MatrixXd g = forces.transpose().partialPivLu().solve(changes.transpose()).transpose();
  const Eigen::LLT<Eigen::MatrixXd> factor(0.5 * (g + g.transpose()));
  if (factor.info() != Eigen::Success)
    return Error{.message = "the reduced step's response is not positive definite", .field = "tissue"};
  const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> v =
      basis * factor.matrixL().toDenseMatrix();
  return ReducedComplianceFactors{r, std::vector<double>(v.data(), v.data() + v.size())};
}

Result<ReducedCoupledNeedleModel> make_coupled_needle_model(const NeedleParameters& needle,
                                                            const NeedleTissueScene& scene, const ReducedModel& tissue,
                                                            const TetMesh& mesh, std::size_t max_point_forces,
                                                            int needle_steps_per_tissue_step) {
  if (auto valid = detail::validate_coupling(scene, max_point_forces, needle_steps_per_tissue_step); !valid)
    return valid.error();
  if (static_cast<std::int64_t>(mesh.nodes_m.size()) != tissue.node_count())
    return Error{.message = "has another node count than the reduced model", .field = "mesh"};
  {
    // The tissue must take max_point_forces point forces in one step.
    auto data = make_reduced_data(tissue);
    if (!data.ok()) return data.error();
    const std::vector<PointForce> none(max_point_forces, PointForce{0, {0.0, 0.0, 0.0}});
    TissueInputs inputs;
    inputs.point_forces = none;
    step(tissue, data.value(), inputs);
    if (data.value().health.has(HealthFlag::bad_sample))
      return Error{.message = "exceeds the reduced model's scene max_point_forces", .field = "max_point_forces"};
  }
  auto factors = reduced_compliance_factors(tissue, kComplianceProbeForceN);
  if (!factors.ok()) return factors.error();
  std::vector<double> rest_m;
  rest_m.reserve(3 * mesh.nodes_m.size());
  for (const Point3& p : mesh.nodes_m) rest_m.insert(rest_m.end(), p.begin(), p.end());
  auto interaction = make_needle_tissue_model(needle, scene, rest_m);
  if (!interaction.ok()) return interaction.error();
  NeedleTissueModel& model = interaction.value();
  model.compliance_rank = factors.value().rank;
  model.compliance_factors = std::move(factors.value().factors);
  return ReducedCoupledNeedleModel{std::move(interaction).value(), &tissue, needle_steps_per_tissue_step,
                                   max_point_forces};
}

Result<ReducedCoupledNeedleData> make_coupled_needle_data(const ReducedCoupledNeedleModel& model,
                                                          const NeedlePose& base) {
  return detail::make_coupled_data(model, base, make_reduced_data(*model.tissue), make_reduced_data(*model.tissue),
                                   static_cast<std::size_t>(model.tissue->node_count()),
                                   refresh_capacity(model.interaction));
}

namespace detail {

void refresh_displacements(const ReducedCoupledNeedleModel& model, ReducedCoupledNeedleData& data) noexcept {
  const ReducedModel& tissue = *model.tissue;
  std::size_t count = 0;
  const auto add = [&](std::int32_t node) {
    if (node >= 0) data.refreshed_nodes[count++] = node;
  };
  for (const LayerState& layer : data.interaction.layers) {
    add(layer.surface.node);
    add(layer.contact.node);
    add(layer.hole.node);
    add(layer.cut_front.node);
  }
  for (const PathPoint& point : data.interaction.path)
    if (point.active) add(point.tissue.node);
  add(data.interaction.tip_anchor.node);
  // The surfaces' vertices the needle can reach before the next tissue step, where they were.
  const NeedleTissueModel& interaction = model.interaction;
  const Eigen::Vector3d base = node_position_m(data.interaction.needle.positions_m, 0);
  const double reach_m = interaction.needle.parameters.length_m + interaction.scene.surface_reach_margin_m;
  for (const detail::SurfaceBvh& bvh : interaction.surface_bvhs)
    for (const std::int32_t node : bvh.vertex_nodes) {
      const auto at = 3 * static_cast<std::size_t>(node);
      const Eigen::Vector3d now(interaction.tissue_rest_m[at] + data.displacements_m[at],
                                interaction.tissue_rest_m[at + 1] + data.displacements_m[at + 1],
                                interaction.tissue_rest_m[at + 2] + data.displacements_m[at + 2]);
      if ((now - base).squaredNorm() <= reach_m * reach_m) add(node);
    }
  const std::int64_t nodes = tissue.node_count();
  for (std::int64_t k = 0; k < std::min(kRefreshBlockNodes, nodes); ++k) {
    add(static_cast<std::int32_t>(data.refresh_cursor));
    data.refresh_cursor = (data.refresh_cursor + 1) % nodes;
  }
  const std::span<double> values = data.refreshed_displacements_m.first(3 * count);
  reconstruct_displacements_m(tissue, data.free_tissue, data.refreshed_nodes.first(count), values);
  for (std::size_t k = 0; k < count; ++k)
    std::copy_n(values.begin() + static_cast<std::ptrdiff_t>(3 * k), 3,
                data.displacements_m.begin() + 3 * static_cast<std::ptrdiff_t>(data.refreshed_nodes[k]));
}

}  // namespace detail

template void step(const ReducedCoupledNeedleModel&, ReducedCoupledNeedleData&, const NeedleInputs&) noexcept;

}  // namespace nav
