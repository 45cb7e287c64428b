#pragma once
// Crossings of a closed triangulated surface with lines parallel to z, counted consistently
// when a line passes exactly through an edge or a vertex, so that crossing parity is a
// reliable inside test.
#include <vector>

#include "nav/mesh/geometry.hpp"
#include "nav/mesher/triangle_bins.hpp"

namespace nav {

/// Casts lines parallel to z through a surface. Each triangle is tested in the x-y plane with
/// edge functions evaluated in one canonical vertex order (lower vertex index first), so the
/// two triangles sharing an edge see exactly opposite values. A line exactly on an edge or a
/// vertex is decided by a fixed tie-break (the edge owns it if it heads up, or left when
/// horizontal), which is the same as moving the line by an infinitesimal (-e, -e^2): the
/// crossing count is that of a line in general position, so its parity is right. Triangles
/// seen edge-on (zero area in x-y) are skipped: the moved line misses them.
class SurfaceRayCaster {
 public:
  /// Keeps a copy of the surface and bins its triangles in x-y.
  explicit SurfaceRayCaster(const TriSurface& surface);

  /// Replaces `z_m` by the z of every crossing of the line through (x, y), ascending.
  void crossings_z(double x_m, double y_m, std::vector<double>& z_m) const;

 private:
  double edge_function(int u, int v, double x_m, double y_m) const;

  TriSurface surface_;
  TriangleBins bins_;
};

}  // namespace nav
