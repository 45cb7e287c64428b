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

double tet_radius_ratio(const Point3& a, const Point3& b, const Point3& c, const Point3& d) {
  // With u, v, w the edges from a and D = u·(v×w) = 6 V: r_in = |D| / (2 S) for the face area
  // sum S, and r_circ = |N| / (2 |D|) with N = |u|²(v×w) + |v|²(w×u) + |w|²(u×v); so the
  // ratio is 3 D² / (S |N|).
  const Point3 u = b - a;
  const Point3 v = c - a;
  const Point3 w = d - a;
  const double six_volume = dot(u, cross(v, w));
  const double area_sum = 0.5 * (norm(cross(u, v)) + norm(cross(v, w)) + norm(cross(w, u)) + norm(cross(c - b, d - b)));
  const double circum = norm(dot(u, u) * cross(v, w) + dot(v, v) * cross(w, u) + dot(w, w) * cross(u, v));
  if (six_volume == 0.0 || area_sum == 0.0 || circum == 0.0) return 0.0;
  return 3.0 * six_volume * six_volume / (area_sum * circum);
}

double tet_min_dihedral_deg(const Point3& a, const Point3& b, const Point3& c, const Point3& d) {
  const std::array<Point3, 4> corners{a, b, c, d};
  std::array<Point3, 4> normals{};
  for (std::size_t f = 0; f < 4; ++f) {
    const auto& face = kTetFaces[f];
    const Point3& p = corners[face[0]];
    normals[f] = cross(corners[face[1]] - p, corners[face[2]] - p);
    const double length = norm(normals[f]);
    if (length == 0.0) return 0.0;
    normals[f] = (1.0 / length) * normals[f];
  }
  constexpr double kPi = 3.14159265358979323846;
  double min_angle_rad = kPi;
  for (std::size_t f = 0; f < 4; ++f) {
    for (std::size_t g = f + 1; g < 4; ++g) {
      // The interior angle at the edge two faces share is pi minus the angle between their normals.
      const double cosine = std::clamp(dot(normals[f], normals[g]), -1.0, 1.0);
      min_angle_rad = std::min(min_angle_rad, kPi - std::acos(cosine));
    }
  }
  return min_angle_rad * 180.0 / kPi;
}

}  // namespace nav
