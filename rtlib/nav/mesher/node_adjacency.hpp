#pragma once
// Per-node adjacency of a tetrahedral mesh: the elements and the neighbours of every node.
#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "nav/mesh/tet_mesh.hpp"

namespace nav {

/// One list of indices per node, stored compressed: node n's list is items[offsets[n] ..
/// offsets[n + 1]).
struct NodeLists {
  std::vector<std::int32_t> offsets;
  std::vector<std::int32_t> items;

  /// The list of node `node`.
  std::span<const std::int32_t> of(std::int32_t node) const {
    return {items.data() + offsets[node], static_cast<std::size_t>(offsets[node + 1] - offsets[node])};
  }
};

/// For every node, the elements that use it, ascending.
NodeLists elements_of_nodes(const TetMesh& mesh);

/// For every node, the nodes it shares an element edge with, ascending and unique.
NodeLists neighbours_of_nodes(const TetMesh& mesh);

/// For every node of 0 .. node_count - 1, the indices of the triangles that use it, ascending.
NodeLists faces_of_nodes(const std::vector<std::array<std::int32_t, 3>>& faces, std::size_t node_count);

}  // namespace nav
