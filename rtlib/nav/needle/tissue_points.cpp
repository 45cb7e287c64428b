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
  TissuePoint point;
  double best_m2 = 0.0;
  const std::size_t nodes = model.tissue_rest_m.size() / 3, displaced = std::min(nodes, displacements_m.size() / 3);
  const double* rest = model.tissue_rest_m.data();
  const double* u = displacements_m.data();
  const double px = position_m.x(), py = position_m.y(), pz = position_m.z();
  // The nearest node now, the first of equals; |current - position|^2 summed x, y, then z.
  const auto consider = [&](std::size_t n, double x, double y, double z) {
    const double dx = x - px, dy = y - py, dz = z - pz;
    const double d2 = (dx * dx + dy * dy) + dz * dz;
    if (point.node < 0 || d2 < best_m2) {
      best_m2 = d2;
      point.node = static_cast<std::int32_t>(n);
    }
  };
  for (std::size_t n = 0; n < displaced; ++n) consider(n, rest[3 * n] + u[3 * n], rest[3 * n + 1] + u[3 * n + 1], rest[3 * n + 2] + u[3 * n + 2]);
  for (std::size_t n = displaced; n < nodes; ++n) consider(n, rest[3 * n], rest[3 * n + 1], rest[3 * n + 2]);
  point.rest_m = position_m - node_displacement(point.node, displacements_m);
  return point;
}

}  // namespace nav
