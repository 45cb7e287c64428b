#pragma once
// Lookup tables of a tetrahedral mesh's boundary: which nodes, edges and faces lie on it.
#include <array>
#include <cstdint>
#include <utility>
#include <vector>

#include "nav/mesh/tet_mesh.hpp"

namespace nav {

/// The boundary faces (used by one element only), their edges and nodes, for lookups.
class BoundaryTopology {
 public:
  /// Builds the tables with extract_boundary.
  explicit BoundaryTopology(const TetMesh& mesh);

  /// True if node `n` is on the boundary.
  bool has_node(std::int32_t n) const;
  /// True if the edge between nodes `a` and `b` is an edge of a boundary face.
  bool has_edge(std::int32_t a, std::int32_t b) const;
  /// Which local faces of `tet` (kTetFaces order: face k is opposite node k) are on the boundary.
  std::array<bool, 4> faces_of(const std::array<std::int32_t, 4>& tet) const;

 private:
  bool has_face(std::int32_t a, std::int32_t b, std::int32_t c) const;

  std::vector<std::int32_t> nodes_;
  std::vector<std::pair<std::int32_t, std::int32_t>> edges_;
  std::vector<std::array<std::int32_t, 3>> faces_;
};

}  // namespace nav
