#pragma once
// The first step of meshing: which lattice tetrahedra make up the domain.
#include <cstdint>
#include <vector>

#include "nav/mesh/tet_mesh.hpp"
#include "nav/mesher/kuhn_lattice.hpp"
#include "nav/mesher/meshing_domain.hpp"

namespace nav {

/// Per lattice tetrahedron (by KuhnLattice::tet_index), 1 if its centroid lies inside
/// `domain`. One classified z column per (i, j, t).
std::vector<std::uint8_t> classify_lattice_tets(const KuhnLattice& lattice, const MeshingDomain& domain);

/// Part of the lattice as a mesh, with an inside flag per element.
struct LatticePatch {
  TetMesh mesh;                      ///< positively oriented elements, nodes in lattice order
  std::vector<std::uint8_t> inside;  ///< per element of `mesh`
};

/// The inside tetrahedra plus every outside tetrahedron that shares a node with one (the
/// room the boundary may move into), in lattice order, with only the nodes they use.
LatticePatch inside_with_envelope(const KuhnLattice& lattice, const std::vector<std::uint8_t>& inside);

}  // namespace nav
