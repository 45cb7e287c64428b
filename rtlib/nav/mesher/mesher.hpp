#pragma once
// The volume mesher: tetrahedralises a domain on a regular grid at a target element size.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "nav/core/error.hpp"
#include "nav/mesh/tet_mesh.hpp"
#include "nav/mesh/validation.hpp"
#include "nav/mesher/boundary_fitting.hpp"
#include "nav/mesher/meshing_domain.hpp"

namespace nav {

/// Settings of make_tet_mesh.
struct MesherOptions {
  double element_size_m = 0.0;  ///< grid spacing h: elements have edges of about h to h sqrt(3)
  double warp_reach = 0.7;      ///< lattice nodes within this many h of the boundary are warped onto it
  FittingOptions fitting;       ///< snapping and smoothing of the staircase mesh
};

/// What make_tet_mesh did and what came out of it.
struct MesherReport {
  std::size_t lattice_cubes = 0;    ///< cubes of the background grid
  std::size_t warped_nodes = 0;     ///< lattice nodes moved onto the boundary before the final choice of elements
  std::size_t boundary_nodes = 0;   ///< nodes on the mesh's boundary, snapped to the domain's
  std::size_t removed_slivers = 0;  ///< ridge and cap elements removed before snapping
  FittingReport fitting;
  TetMeshReport quality;  ///< counts, volume, inverted elements, radius ratio, angles
};

/// A mesh made by make_tet_mesh, with its boundary nodes (ascending).
struct MesherOutput {
  TetMesh mesh;
  std::vector<std::int32_t> boundary_nodes;
  MesherReport report;
};

/// Tetrahedralises `domain` at element size h = element_size_m:
///  1. a Kuhn lattice of spacing h over the domain's bounds; its elements whose centroid is
///     inside make a staircase approximation;
///  2. lattice nodes near the boundary (within warp_reach h, on an element that crosses it)
///     are warped onto it, and the elements around them chosen again by centroid, flat ones
///     dropped (warp_to_boundary);
///  3. boundary elements that stick out with all four nodes on the boundary, which snapping
///     would flatten, are removed (remove_boundary_slivers);
///  4. the remaining boundary nodes are snapped onto the boundary, the interior is smoothed
///     (fit_to_boundary).
/// Every move is guarded (GuardedNodeMover): no element is ever inverted or flattened, every
/// element is positively oriented; a node the guard keeps off the boundary is reported.
/// tet_regions is left empty. Deterministic: the same domain and options give bitwise the
/// same mesh. Errors: a size that is not positive, a grid of more than 2^24 cubes, or no
/// element inside.
Result<MesherOutput> make_tet_mesh(const MeshingDomain& domain, const MesherOptions& options);

/// The element size h = cbrt(6 V / N) at which make_tet_mesh gives about `tet_count`
/// elements for a domain of volume `volume_m3` (a lattice element has volume h^3 / 6).
double element_size_for_tet_count_m(double volume_m3, double tet_count);

}  // namespace nav
