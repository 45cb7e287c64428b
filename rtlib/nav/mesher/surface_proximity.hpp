#pragma once
// Exact closest points on a triangulated surface, searched through a bucket grid.
#include "nav/mesh/geometry.hpp"
#include "nav/mesher/triangle_bins.hpp"

namespace nav {

/// Answers "which point of the surface is closest to p?" exactly (up to rounding). Cells are
/// searched in growing shells around p's cell until no unvisited triangle can be closer.
class SurfaceProximity {
 public:
  /// Keeps a copy of the surface and bins its triangles in 3-D.
  explicit SurfaceProximity(const TriSurface& surface);

  /// The closest point of the surface to `point_m` (the point itself for an empty surface).
  Point3 closest_point(const Point3& point_m) const;

 private:
  /// Distance from `point_m` below which no triangle outside the searched cells can lie.
  double unvisited_distance_m(const Point3& point_m, const std::array<int, 3>& centre, int radius) const;

  TriSurface surface_;
  TriangleBins bins_;
};

}  // namespace nav
