#include "nav/mesher/kuhn_lattice.hpp"

#include <cmath>

namespace nav {
namespace {

/// Tetrahedron t walks from the cube's lowest corner to its highest along the axes
/// kAxisOrder[t][0], [1], [2]; its orientation is the parity of that permutation.
constexpr int kAxisOrder[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
constexpr bool kOddPermutation[6] = {false, true, true, false, false, true};

}  // namespace

Point3 KuhnLattice::node_position_m(std::int64_t node) const {
  const std::int64_t nx = cubes[0] + 1;
  const std::int64_t ny = cubes[1] + 1;
  const std::int64_t index[3] = {node % nx, (node / nx) % ny, node / (nx * ny)};
  Point3 position{};
  for (int a = 0; a < 3; ++a) position[a] = anchor_m[a] + static_cast<double>(index[a] - 1) * spacing_m;
  return position;
}

std::array<std::int64_t, 4> KuhnLattice::tet_nodes(std::int64_t i, std::int64_t j, std::int64_t k, int t) const {
  std::int64_t corner[3] = {i, j, k};
  std::array<std::int64_t, 4> nodes{};
  nodes[0] = node_index(corner[0], corner[1], corner[2]);
  for (int step = 0; step < 3; ++step) {
    ++corner[kAxisOrder[t][step]];
    nodes[step + 1] = node_index(corner[0], corner[1], corner[2]);
  }
  if (kOddPermutation[t]) std::swap(nodes[1], nodes[2]);
  return nodes;
}

Point3 KuhnLattice::centroid_offset(int t) {
  // The path's vertices (0, e_a, e_a + e_b, 1) average to 3/4 along a, 1/2 along b, 1/4 along c.
  Point3 offset{};
  offset[kAxisOrder[t][0]] = 0.75;
  offset[kAxisOrder[t][1]] = 0.5;
  offset[kAxisOrder[t][2]] = 0.25;
  return offset;
}

KuhnLattice lattice_over(const Bounds3& bounds, double spacing_m) {
  KuhnLattice lattice;
  lattice.anchor_m = bounds.min_m;
  lattice.spacing_m = spacing_m;
  for (int a = 0; a < 3; ++a) {
    lattice.cubes[a] = static_cast<std::int64_t>(std::ceil((bounds.max_m[a] - bounds.min_m[a]) / spacing_m)) + 2;
  }
  return lattice;
}

}  // namespace nav
