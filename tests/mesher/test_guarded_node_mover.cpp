// The inversion guard: a move that would invert or flatten an element is cut back.
#include <gtest/gtest.h>

#include "nav/mesh/geometry.hpp"
#include "nav/mesher/guarded_node_mover.hpp"

namespace nav {
namespace {

TetMesh two_tetrahedra() {
  // Two positive elements sharing the face (0, 1, 2); node 3 above it, node 4 below.
  TetMesh mesh;
  mesh.nodes_m = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.3, 0.3, 1.0}, {0.3, 0.3, -1.0}};
  mesh.tets = {{0, 1, 2, 3}, {0, 2, 1, 4}};
  return mesh;
}

TEST(GuardedNodeMover, TakesHarmlessMovesWhole) {
  TetMesh mesh = two_tetrahedra();
  GuardedNodeMover mover(mesh);
  EXPECT_EQ(mover.move_towards(3, {0.25, 0.25, 1.2}, 0.1, 6), 1.0);
  EXPECT_EQ(mesh.nodes_m[3], (Point3{0.25, 0.25, 1.2}));
}

TEST(GuardedNodeMover, NeverInvertsOrFlattens) {
  TetMesh mesh = two_tetrahedra();
  GuardedNodeMover mover(mesh);
  // Straight through the shared face: the whole move would invert element 0.
  const double fraction = mover.move_towards(3, {0.3, 0.3, -0.5}, 0.1, 6);
  EXPECT_LT(fraction, 1.0);
  EXPECT_GT(signed_tet_volume_m3(mesh, 0), 0.0);
  EXPECT_GE(mover.min_quality_around(3), 0.1);
  // A move that no halving can save leaves the node where it was.
  const Point3 before = mesh.nodes_m[4];
  EXPECT_EQ(mover.move_towards(4, {0.3, 0.3, 5.0}, 0.1, 0), 0.0);
  EXPECT_EQ(mesh.nodes_m[4], before);
}

}  // namespace
}  // namespace nav
