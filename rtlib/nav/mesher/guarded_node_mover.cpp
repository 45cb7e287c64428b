#include "nav/mesher/guarded_node_mover.hpp"

#include <algorithm>

#include "nav/mesh/geometry.hpp"

namespace nav {

GuardedNodeMover::GuardedNodeMover(TetMesh& mesh) : mesh_(mesh), elements_of_node_(elements_of_nodes(mesh)) {}

double GuardedNodeMover::min_quality_around(std::int32_t node) const {
  double quality = 1.0;
  for (const std::int32_t e : elements_of_node_.of(node)) {
    const auto& tet = mesh_.tets[e];
    const Point3& a = mesh_.nodes_m[tet[0]];
    const Point3& b = mesh_.nodes_m[tet[1]];
    const Point3& c = mesh_.nodes_m[tet[2]];
    const Point3& d = mesh_.nodes_m[tet[3]];
    // An inverted or flat element counts as quality 0, which the guard never accepts.
    quality = std::min(quality, signed_tet_volume_m3(a, b, c, d) > 0.0 ? tet_radius_ratio(a, b, c, d) : 0.0);
  }
  return quality;
}

double GuardedNodeMover::move_towards(std::int32_t node, const Point3& target_m, double quality_floor,
                                      int max_halvings) {
  Point3& position = mesh_.nodes_m[node];
  const Point3 start = position;
  const double required = std::min(quality_floor, min_quality_around(node));
  double fraction = 1.0;
  for (int attempt = 0; attempt <= max_halvings; ++attempt, fraction *= 0.5) {
    position = start + fraction * (target_m - start);
    const double quality = min_quality_around(node);
    if (quality > 0.0 && quality >= required) return fraction;
  }
  position = start;
  return 0.0;
}

}  // namespace nav
