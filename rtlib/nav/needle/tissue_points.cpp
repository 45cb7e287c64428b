#include "nav/needle/tissue_points.hpp"

#include <algorithm>

namespace nav {

namespace {

Eigen::Vector3d node_displacement(std::int32_t node, std::span<const double> displacements_m) {
  if (node < 0 || displacements_m.size() < 3 * static_cast<std::size_t>(node) + 3) return Eigen::Vector3d::Zero();
  return Eigen::Map<const Eigen::Vector3d>(displacements_m.data() + 3 * static_cast<std::size_t>(node));
}

}  // namespace

Eigen::Vector3d tissue_point_position_m(const TissuePoint& point, std::span<const double> displacements_m) noexcept {
  return point.rest_m + node_displacement(point.node, displacements_m);
}

TissuePoint tissue_point_at(const NeedleTissueModel& model, const Eigen::Vector3d& position_m,
                            std::span<const double> displacements_m) noexcept {
  detail::NearestNodeQuery query;
  query.rest_m = model.tissue_rest_m.data();
  query.displacements_m = displacements_m.data();
  query.nodes = model.tissue_rest_m.size() / 3;
  query.displaced = std::min(query.nodes, displacements_m.size() / 3);
  for (int c = 0; c < 3; ++c) query.point_m[c] = position_m[c];
  TissuePoint point;
  point.node = model.lane_kernels->nearest_node(query);
  point.rest_m = position_m - node_displacement(point.node, displacements_m);
  return point;
}

}  // namespace nav
