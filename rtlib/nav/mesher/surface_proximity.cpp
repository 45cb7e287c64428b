#include "nav/mesher/surface_proximity.hpp"

#include <algorithm>
#include <limits>

#include "nav/mesher/closest_point.hpp"

namespace nav {

SurfaceProximity::SurfaceProximity(const TriSurface& surface)
    : surface_(surface),
      bins_(surface, bounds_of(surface.vertices_m), triangle_bin_counts(surface, bounds_of(surface.vertices_m), 128)) {}

double SurfaceProximity::unvisited_distance_m(const Point3& point_m, const std::array<int, 3>& centre,
                                              int radius) const {
  double distance_m = std::numeric_limits<double>::infinity();
  const auto cells = bins_.cells();
  for (int a = 0; a < 3; ++a) {
    const double cell_m = bins_.cell_size_m()[a];
    if (centre[a] - radius > 0) {
      const double lo_m = bins_.box().min_m[a] + (centre[a] - radius) * cell_m;
      distance_m = std::min(distance_m, std::max(0.0, point_m[a] - lo_m));
    }
    if (centre[a] + radius < cells[a] - 1) {
      const double hi_m = bins_.box().min_m[a] + (centre[a] + radius + 1) * cell_m;
      distance_m = std::min(distance_m, std::max(0.0, hi_m - point_m[a]));
    }
  }
  return distance_m;
}

Point3 SurfaceProximity::closest_point(const Point3& point_m) const {
  if (surface_.triangles.empty()) return point_m;
  const auto centre = bins_.cell_of(point_m);
  const auto cells = bins_.cells();
  const int max_radius = std::max({cells[0], cells[1], cells[2]});
  Point3 best = point_m;
  double best_squared = std::numeric_limits<double>::infinity();
  for (int r = 0; r <= max_radius; ++r) {
    // Visit the shell of cells at Chebyshev distance r from the centre cell.
    for (int k = std::max(centre[2] - r, 0); k <= std::min(centre[2] + r, cells[2] - 1); ++k) {
      for (int j = std::max(centre[1] - r, 0); j <= std::min(centre[1] + r, cells[1] - 1); ++j) {
        for (int i = std::max(centre[0] - r, 0); i <= std::min(centre[0] + r, cells[0] - 1); ++i) {
          const int shell = std::max({std::abs(i - centre[0]), std::abs(j - centre[1]), std::abs(k - centre[2])});
          if (shell != r) continue;
          for (const std::int32_t t : bins_.triangles_in(i, j, k)) {
            const auto& tri = surface_.triangles[t];
            const Point3 q = closest_point_on_triangle(point_m, surface_.vertices_m[tri[0]],
                                                       surface_.vertices_m[tri[1]], surface_.vertices_m[tri[2]]);
            const double d2 = dot(q - point_m, q - point_m);
            if (d2 < best_squared) {
              best_squared = d2;
              best = q;
            }
          }
        }
      }
    }
    const double bound_m = unvisited_distance_m(point_m, centre, r);
    if (best_squared <= bound_m * bound_m) break;
  }
  return best;
}

}  // namespace nav
