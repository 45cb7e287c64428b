#include "nav/mesher/surface_ray_caster.hpp"

#include <algorithm>

namespace nav {
namespace {

Bounds3 flattened_in_z(Bounds3 box) {
  box.min_m[2] = 0.0;
  box.max_m[2] = 0.0;
  return box;
}

Bounds3 xy_bounds(const TriSurface& surface) { return flattened_in_z(bounds_of(surface.vertices_m)); }

/// Top-left style tie-break: an edge traversed counter-clockwise along `dx, dy` owns the
/// points lying exactly on it when it heads up, or left if horizontal. Of the two opposite
/// traversals of a shared edge exactly one owns it.
bool owns_edge(double dx, double dy) { return dy > 0.0 || (dy == 0.0 && dx < 0.0); }

}  // namespace

SurfaceRayCaster::SurfaceRayCaster(const TriSurface& surface)
    : surface_(surface), bins_(surface, xy_bounds(surface), triangle_bin_counts(surface, xy_bounds(surface), 512)) {}

double SurfaceRayCaster::edge_function(int u, int v, double x_m, double y_m) const {
  if (u > v) return -edge_function(v, u, x_m, y_m);
  const Point3& a = surface_.vertices_m[u];
  const Point3& b = surface_.vertices_m[v];
  return (b[0] - a[0]) * (y_m - a[1]) - (b[1] - a[1]) * (x_m - a[0]);
}

void SurfaceRayCaster::crossings_z(double x_m, double y_m, std::vector<double>& z_m) const {
  z_m.clear();
  const auto cell = bins_.cell_of({x_m, y_m, 0.0});
  for (const std::int32_t t : bins_.triangles_in(cell[0], cell[1], 0)) {
    const auto& tri = surface_.triangles[t];
    const Point3& a = surface_.vertices_m[tri[0]];
    const Point3& b = surface_.vertices_m[tri[1]];
    const Point3& c = surface_.vertices_m[tri[2]];
    const double area2 = (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
    if (area2 == 0.0) continue;
    const double sign = area2 > 0.0 ? 1.0 : -1.0;
    // Edge e goes from vertex e to vertex e+1; w[e] > 0 on the triangle's side of it.
    double w[3];
    bool covered = true;
    for (int e = 0; e < 3 && covered; ++e) {
      const int u = tri[e];
      const int v = tri[(e + 1) % 3];
      w[e] = sign * edge_function(u, v, x_m, y_m);
      const Point3& pu = surface_.vertices_m[u];
      const Point3& pv = surface_.vertices_m[v];
      covered = w[e] > 0.0 || (w[e] == 0.0 && owns_edge(sign * (pv[0] - pu[0]), sign * (pv[1] - pu[1])));
    }
    if (!covered) continue;
    // Barycentric weights: the weight of a vertex is the edge function of its opposite edge.
    const double total = w[0] + w[1] + w[2];
    z_m.push_back((w[1] * a[2] + w[2] * b[2] + w[0] * c[2]) / total);
  }
  std::sort(z_m.begin(), z_m.end());
}

}  // namespace nav
