#pragma once
// Moves mesh nodes one at a time without ever inverting or flattening an element.
#include <cstdint>

#include "nav/mesh/tet_mesh.hpp"
#include "nav/mesher/node_adjacency.hpp"

namespace nav {

/// Moves single nodes of a mesh (held by reference) under an inversion guard: a move is
/// taken only if every element around the node keeps a positive radius ratio of at least
/// min(quality_floor, the smallest ratio around the node before the move); otherwise the move
/// is halved and retried.
class GuardedNodeMover {
 public:
  /// Guards moves in `mesh`, whose elements must not change while the mover is used.
  explicit GuardedNodeMover(TetMesh& mesh);

  /// Moves `node` towards `target_m`: all the way, or the largest of 1/2, 1/4, ...
  /// (`max_halvings` times) that passes the guard. Returns the fraction moved, 0 if none.
  double move_towards(std::int32_t node, const Point3& target_m, double quality_floor, int max_halvings);

  /// The smallest radius ratio of the elements around `node` (0 if one is inverted or flat).
  double min_quality_around(std::int32_t node) const;

 private:
  TetMesh& mesh_;
  NodeLists elements_of_node_;
};

}  // namespace nav
