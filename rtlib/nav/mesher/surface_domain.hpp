#pragma once
// A region bounded by a closed triangulated surface (e.g. a liver surface from an OBJ file).
#include "nav/mesher/meshing_domain.hpp"
#include "nav/mesher/surface_proximity.hpp"
#include "nav/mesher/surface_ray_caster.hpp"

namespace nav {

/// The region enclosed by a closed (watertight) triangulated surface. Inside is decided by
/// the parity of a z-parallel line's crossings with the surface (one line per grid column,
/// robust to lines through edges and vertices; the triangles' orientation does not matter);
/// projection is the exact closest point on the triangles.
class SurfaceDomain final : public MeshingDomain {
 public:
  /// Keeps what it needs of `surface` (coordinates in metres).
  explicit SurfaceDomain(const TriSurface& surface);

  Bounds3 bounds() const override { return bounds_; }
  bool contains(const Point3& point_m) const override;
  void classify_column(double x_m, double y_m, double z0_m, double dz_m, std::span<std::uint8_t> inside) const override;
  Point3 project_to_boundary(const Point3& point_m) const override { return proximity_.closest_point(point_m); }

 private:
  Bounds3 bounds_;
  SurfaceRayCaster rays_;
  SurfaceProximity proximity_;
};

}  // namespace nav
