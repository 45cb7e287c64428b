#include "nav/mesh/geometry.hpp"

#include <algorithm>
#include <cmath>

namespace nav {

double norm(const Point3& a) { return std::sqrt(dot(a, a)); }

double signed_tet_volume_m3(const Point3& a, const Point3& b, const Point3& c, const Point3& d) {
  return dot(b - a, cross(c - a, d - a)) / 6.0;
}

double signed_tet_volume_m3(const TetMesh& mesh, std::size_t tet) {
  const auto& t = mesh.tets[tet];
  return signed_tet_volume_m3(mesh.nodes_m[t[0]], mesh.nodes_m[t[1]], mesh.nodes_m[t[2]], mesh.nodes_m[t[3]]);
}

double total_volume_m3(const TetMesh& mesh) {
  double volume = 0.0;
  for (std::size_t e = 0; e < mesh.tets.size(); ++e) volume += signed_tet_volume_m3(mesh, e);
  return volume;
}

double enclosed_volume_m3(const TriSurface& surface) {
  double volume = 0.0;
  for (const auto& tri : surface.triangles) {
    const Point3& a = surface.vertices_m[tri[0]];
    volume += dot(a, cross(surface.vertices_m[tri[1]], surface.vertices_m[tri[2]])) / 6.0;
  }
  return volume;
}

Bounds3 bounds_of(const std::vector<Point3>& points_m) {
  Bounds3 bounds;
  if (points_m.empty()) return bounds;
  bounds.min_m = bounds.max_m = points_m.front();
  for (const Point3& p : points_m) {
    for (int k = 0; k < 3; ++k) {
      bounds.min_m[k] = std::min(bounds.min_m[k], p[k]);
      bounds.max_m[k] = std::max(bounds.max_m[k], p[k]);
    }
  }
  return bounds;
}

}  // namespace nav
