#pragma once
// Moves the lattice nodes that lie close to the boundary onto it before the final choice of
// elements, so that the mesh's boundary is made mostly of nodes already on the domain's.
#include <cstdint>
#include <vector>

#include "nav/mesh/tet_mesh.hpp"
#include "nav/mesher/meshing_domain.hpp"

namespace nav {

/// Settings of warp_to_boundary.
struct WarpOptions {
  double reach_m = 0.0;        ///< nodes at most this far from the boundary are moved onto it
  double quality_floor = 0.1;  ///< guard of the moves (see GuardedNodeMover)
};

/// For every node (ascending) that is touched by both an inside and an outside element, or
/// lies on an element with nodes on both sides of the boundary, moves it onto the boundary if
/// its projection is within reach and the guard accepts the whole move; then re-decides
/// `inside` for the elements around moved nodes: centroid inside, and, if all four nodes were
/// moved onto the boundary, a radius ratio of at least the floor (else it is a sliver lying on
/// the boundary). Returns the number of nodes moved.
std::size_t warp_to_boundary(TetMesh& mesh, std::vector<std::uint8_t>& inside, const MeshingDomain& domain,
                             const WarpOptions& options);

}  // namespace nav
