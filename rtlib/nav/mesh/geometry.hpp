#pragma once
// Small geometric kernels on Point3 used by loaders, validation and the mesher.
#include "nav/mesh/tet_mesh.hpp"

namespace nav {

inline Point3 operator-(const Point3& a, const Point3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
inline Point3 operator+(const Point3& a, const Point3& b) { return {a[0] + b[0], a[1] + b[1], a[2] + b[2]}; }
inline Point3 operator*(double s, const Point3& a) { return {s * a[0], s * a[1], s * a[2]}; }
inline double dot(const Point3& a, const Point3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
inline Point3 cross(const Point3& a, const Point3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double norm(const Point3& a);

/// Signed volume of the tetrahedron (a, b, c, d) in m^3; positive when positively oriented.
double signed_tet_volume_m3(const Point3& a, const Point3& b, const Point3& c, const Point3& d);

/// Signed volume of element `tet` of `mesh` in m^3.
double signed_tet_volume_m3(const TetMesh& mesh, std::size_t tet);

/// Sum of the signed volumes of all elements, in m^3.
double total_volume_m3(const TetMesh& mesh);

/// Volume enclosed by a closed, outward oriented surface (divergence theorem), in m^3.
double enclosed_volume_m3(const TriSurface& surface);

/// Axis-aligned bounds of a point set.
struct Bounds3 {
  Point3 min_m{};
  Point3 max_m{};
};
Bounds3 bounds_of(const std::vector<Point3>& points_m);

/// The four faces of a tetrahedron (a0, a1, a2, a3) as local vertex triples, each ordered
/// counter-clockwise seen from outside when the element is positively oriented; face k is
/// the one opposite vertex k.
inline constexpr std::array<std::array<int, 3>, 4> kTetFaces{{{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}}};

/// Normalised radius ratio 3 r_in / r_circ of the tetrahedron (a, b, c, d): 1 for the regular
/// tetrahedron, tending to 0 as it flattens (0 when flat). Independent of orientation.
double tet_radius_ratio(const Point3& a, const Point3& b, const Point3& c, const Point3& d);

/// The smallest of the six interior dihedral angles of the tetrahedron (a, b, c, d), in
/// degrees: 70.53 (acos 1/3) for the regular tetrahedron, 0 when flat. Independent of orientation.
double tet_min_dihedral_deg(const Point3& a, const Point3& b, const Point3& c, const Point3& d);

}  // namespace nav
