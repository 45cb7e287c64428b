#pragma once
// Extracting part of a tetrahedral mesh.
#include <cstdint>
#include <vector>

#include "nav/mesh/tet_mesh.hpp"

namespace nav {

/// The elements of `mesh` flagged in `keep` (in their order, with their regions if any) and
/// only the nodes they use, renumbered in their original order.
TetMesh mesh_subset(const TetMesh& mesh, const std::vector<std::uint8_t>& keep);

}  // namespace nav
