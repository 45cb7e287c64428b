// The background lattice: six positive tetrahedra per cube that fill it and conform across cubes.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <map>

#include "nav/mesh/geometry.hpp"
#include "nav/mesher/kuhn_lattice.hpp"

namespace nav {
namespace {

TEST(KuhnLattice, SixPositiveTetrahedraFillEachCube) {
  const KuhnLattice lattice = lattice_over({{0.0, 0.0, 0.0}, {0.01, 0.01, 0.01}}, 0.005);
  const double h = lattice.spacing_m;
  double volume = 0.0;
  for (int t = 0; t < KuhnLattice::kTetsPerCube; ++t) {
    const auto nodes = lattice.tet_nodes(1, 2, 0, t);
    const double v = signed_tet_volume_m3(lattice.node_position_m(nodes[0]), lattice.node_position_m(nodes[1]),
                                          lattice.node_position_m(nodes[2]), lattice.node_position_m(nodes[3]));
    EXPECT_NEAR(v, h * h * h / 6.0, 1e-20) << t;
    volume += v;
    // The centroid offset is the mean of the nodes, relative to the cube's lowest corner.
    Point3 mean{};
    for (const auto n : nodes) mean = mean + lattice.node_position_m(n);
    const Point3 corner = lattice.node_position_m(lattice.node_index(1, 2, 0));
    const Point3 offset = KuhnLattice::centroid_offset(t);
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(0.25 * mean[a] - corner[a], offset[a] * h, 1e-15);
  }
  EXPECT_NEAR(volume, h * h * h, 1e-20);
}

TEST(KuhnLattice, NeighbouringCubesShareWholeFaces) {
  const KuhnLattice lattice = lattice_over({{0.0, 0.0, 0.0}, {0.0, 0.0, 0.0}}, 1.0);  // 2 x 2 x 2 cubes
  ASSERT_EQ(lattice.cubes, (std::array<std::int64_t, 3>{2, 2, 2}));
  std::map<std::array<std::int64_t, 3>, int> uses;
  for (std::int64_t k = 0; k < 2; ++k)
    for (std::int64_t j = 0; j < 2; ++j)
      for (std::int64_t i = 0; i < 2; ++i)
        for (int t = 0; t < KuhnLattice::kTetsPerCube; ++t) {
          const auto nodes = lattice.tet_nodes(i, j, k, t);
          for (const auto& face : kTetFaces) {
            std::array<std::int64_t, 3> key{nodes[face[0]], nodes[face[1]], nodes[face[2]]};
            std::sort(key.begin(), key.end());
            ++uses[key];
          }
        }
  int outer = 0;
  for (const auto& [face, count] : uses) {
    EXPECT_LE(count, 2);
    outer += count == 1 ? 1 : 0;
  }
  EXPECT_EQ(outer, 6 * 4 * 2);  // two triangles per square of the outer surface
}

}  // namespace
}  // namespace nav
