#pragma once
// Moves the boundary nodes of a staircase mesh onto the boundary they approximate and relaxes
// the nodes inside, never inverting an element.
#include <array>
#include <cstdint>
#include <vector>

#include "nav/mesh/tet_mesh.hpp"
#include "nav/mesher/meshing_domain.hpp"

namespace nav {

/// The mesh's boundary to be fitted onto a domain's: its nodes (ascending) and its faces (node
/// triples, used to find the creases to keep). The domain is not owned.
struct BoundaryToFit {
  std::vector<std::int32_t> nodes;
  std::vector<std::array<std::int32_t, 3>> faces;
  const MeshingDomain* domain = nullptr;
};

/// How hard boundary fitting tries, and how much element quality a snap may cost.
struct FittingOptions {
  double relaxation = 0.7;            ///< pull of a boundary node towards its boundary neighbours' mean
  int passes = 4;                     ///< snapping passes, each followed by smoothing sweeps
  int smoothing_sweeps = 2;           ///< sweeps of guarded Laplacian smoothing of the interior nodes
  double quality_floor = 0.1;         ///< a snap may lower the radius ratios around a node to this
  int max_halvings = 6;               ///< a blocked move is halved at most this many times
  double snapped_tolerance_m = 1e-8;  ///< a node this close to its projection counts as snapped
  double crease_cosine = 0.3;         ///< snapped faces bending more than this (72.5 deg) make a crease
};

/// What boundary fitting achieved.
struct FittingReport {
  std::vector<std::int32_t> unsnapped_nodes;  ///< nodes the guard kept off the boundary, ascending
  double max_gap_m = 0.0;                     ///< largest distance of a node to its projection
};

/// Moves every node of `boundary` onto its domain's boundary and smooths the other nodes, in
/// `passes` passes and a final snap, every move under the inversion guard of GuardedNodeMover:
///  - snap: a node aims at the projection of a point pulled (by `relaxation`) towards the mean
///    of its boundary neighbours, so that nodes stacked along the normal (staircase risers)
///    spread out along the boundary instead of meeting; a node already on the boundary and on
///    a crease (edge or corner of the domain) stays; the final snap does not pull;
///  - smoothing: an interior node moves towards the mean of its neighbours if that does not
///    lower the smallest radius ratio around it.
/// Deterministic: nodes are visited in ascending order.
FittingReport fit_to_boundary(TetMesh& mesh, const BoundaryToFit& boundary, const FittingOptions& options);

}  // namespace nav
