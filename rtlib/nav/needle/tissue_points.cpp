#include "nav/needle/tissue_points.hpp"

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
  TissuePoint point;
  double best_m2 = 0.0;
  const std::size_t nodes = model.tissue_rest_m.size() / 3;
  for (std::size_t n = 0; n < nodes; ++n) {
    const Eigen::Vector3d current = Eigen::Map<const Eigen::Vector3d>(model.tissue_rest_m.data() + 3 * n) +
                                    node_displacement(static_cast<std::int32_t>(n), displacements_m);
    const double d2 = (current - position_m).squaredNorm();
    if (point.node < 0 || d2 < best_m2) {
      best_m2 = d2;
      point.node = static_cast<std::int32_t>(n);
    }
  }
  point.rest_m = position_m - node_displacement(point.node, displacements_m);
  return point;
}

}  // namespace nav
