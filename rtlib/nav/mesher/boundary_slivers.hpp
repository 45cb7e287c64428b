#pragma once
// Prepares a staircase mesh for snapping: an element with all four nodes on the boundary that
// sticks out of it would be flattened onto the surface by the snap.
#include <cstddef>

#include "nav/mesh/tet_mesh.hpp"
#include "nav/mesher/meshing_domain.hpp"

namespace nav {

/// What remove_boundary_slivers spares.
struct SliverOptions {
  double crease_cosine = 0.3;  ///< boundary faces bending more than this make an edge or corner
  double tolerance_m = 1e-8;   ///< a node this close to the domain's boundary is on it
};

/// Removes the elements that have all four nodes on the mesh's boundary and stick out of it,
/// repeatedly while new ones appear: snapping would flatten them onto the domain's boundary.
/// Sticking out: ridges (two boundary faces, the edge their two other faces share not on the
/// boundary) and caps (three or four boundary faces); both removals keep a manifold boundary
/// manifold. Spared: elements on an edge or corner of the domain (nodes on its boundary, two
/// boundary faces bending by more than the crease angle). Nodes left without elements are
/// dropped; the order of what remains is kept. Returns the number of elements removed.
std::size_t remove_boundary_slivers(TetMesh& mesh, const MeshingDomain& domain, const SliverOptions& options);

}  // namespace nav
