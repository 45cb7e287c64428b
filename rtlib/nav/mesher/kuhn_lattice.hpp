#pragma once
// The background grid of the mesher: cubes split into six tetrahedra each.
#include <array>
#include <cstdint>

#include "nav/mesh/geometry.hpp"

namespace nav {

/// A regular grid of cubes of edge spacing_m, each split into the six tetrahedra of Kuhn's
/// (Freudenthal's) triangulation around its main diagonal. Every cube is split the same way,
/// so the tetrahedra of neighbouring cubes share whole faces. Nodes are numbered x fastest;
/// node (i, j, k) sits at anchor_m + (i - 1, j - 1, k - 1) spacing_m, i.e. the grid has one
/// cube of margin below the anchor.
struct KuhnLattice {
  static constexpr int kTetsPerCube = 6;

  Point3 anchor_m{};
  double spacing_m = 0.0;
  std::array<std::int64_t, 3> cubes{};  ///< cubes per axis

  /// Number of lattice nodes ((cubes + 1) per axis).
  std::int64_t node_count() const { return (cubes[0] + 1) * (cubes[1] + 1) * (cubes[2] + 1); }
  /// Index of node (i, j, k).
  std::int64_t node_index(std::int64_t i, std::int64_t j, std::int64_t k) const {
    return i + (cubes[0] + 1) * (j + (cubes[1] + 1) * k);
  }
  /// Position of node `node`.
  Point3 node_position_m(std::int64_t node) const;
  /// Index of tetrahedron `t` (0..5) of cube (i, j, k): cubes x fastest, six per cube.
  std::int64_t tet_index(std::int64_t i, std::int64_t j, std::int64_t k, int t) const {
    return (i + cubes[0] * (j + cubes[1] * k)) * kTetsPerCube + t;
  }
  /// Lattice nodes of tetrahedron `t` (0..5) of cube (i, j, k), positively oriented.
  std::array<std::int64_t, 4> tet_nodes(std::int64_t i, std::int64_t j, std::int64_t k, int t) const;
  /// Centroid of tetrahedron `t` relative to its cube's lowest corner, in units of the spacing.
  static Point3 centroid_offset(int t);
};

/// The lattice of spacing `spacing_m` whose anchor is `bounds.min_m` and whose cubes cover
/// `bounds` with one cube of margin on every side.
KuhnLattice lattice_over(const Bounds3& bounds, double spacing_m);

}  // namespace nav
