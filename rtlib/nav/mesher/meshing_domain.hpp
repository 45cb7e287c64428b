#pragma once
// What a volume mesher needs to know about the region it fills, whatever the region's source:
// a closed triangulated surface, a label volume (segmentation) or an implicit function.
#include <cstddef>
#include <cstdint>
#include <span>

#include "nav/mesh/geometry.hpp"

namespace nav {

/// A bounded region of space to be tetrahedralised (lengths in metres). Implementations answer
/// inside tests and project points onto the region's boundary. Queries are const and
/// deterministic: the same point always gets the same answer.
class MeshingDomain {
 public:
  virtual ~MeshingDomain() = default;

  /// An axis-aligned box that contains the whole region.
  virtual Bounds3 bounds() const = 0;

  /// True if the point lies inside the region.
  virtual bool contains(const Point3& point_m) const = 0;

  /// Writes to inside[k] whether the point (x, y, z0 + k dz) lies inside, for every k of the
  /// span (dz_m >= 0). The default asks contains() point by point; surfaces answer a whole
  /// column with one ray.
  virtual void classify_column(double x_m, double y_m, double z0_m, double dz_m, std::span<std::uint8_t> inside) const;

  /// The boundary point that `point_m` is snapped to: the closest point of a surface, or the
  /// crossing of a field's boundary level along the field's gradient.
  virtual Point3 project_to_boundary(const Point3& point_m) const = 0;

 protected:
  MeshingDomain() = default;
  MeshingDomain(const MeshingDomain&) = default;
  MeshingDomain& operator=(const MeshingDomain&) = default;
};

}  // namespace nav
