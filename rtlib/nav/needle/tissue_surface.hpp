#pragma once
// The puncturable surfaces of a tetrahedral mesh, for the needle's layers (init time): the
// mesh's boundary (an organ's capsule) and the boundary of a tagged region (a tumour, a
// vessel of a label volume), as triangles on the mesh's nodes, so that they move with them.
#include <cstdint>

#include "nav/core/error.hpp"
#include "nav/mesh/tet_mesh.hpp"
#include "nav/needle/needle_tissue_scene.hpp"

namespace nav {

/// The boundary of the whole mesh, outward (for positively oriented elements).
TissueSurface mesh_boundary_surface(const TetMesh& mesh);

/// The boundary of the elements whose tet_regions tag is `region`, outward: its faces that
/// no other element of the region shares. The Error says when no element carries the tag.
Result<TissueSurface> region_boundary_surface(const TetMesh& mesh, std::int32_t region);

}  // namespace nav
