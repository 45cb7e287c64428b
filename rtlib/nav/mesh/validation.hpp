#pragma once
// Init-time checks of meshes before models are built on them: element orientation and shape
// quality of tetrahedral meshes, closedness and orientation of surfaces, and the boundary
// surface of a tetrahedral mesh.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "nav/mesh/tet_mesh.hpp"

namespace nav {

/// Elements whose normalised radius ratio (3 r_in / r_circ) is below this are counted as
/// degenerate (slivers, needles, caps, flat elements). 0.05 flags elements whose inscribed
/// sphere is under 1/60 of their circumsphere: far beyond what a mesher produces on purpose,
/// and enough to ruin the conditioning of a linear FEM stiffness.
constexpr double kDegenerateRadiusRatio = 0.05;

/// What validate_tet_mesh found. Elements with an out-of-range index are counted there and
/// left out of every geometric figure.
struct TetMeshReport {
  std::size_t nodes = 0;
  std::size_t tetrahedra = 0;
  double volume_m3 = 0.0;                                   ///< sum of the signed element volumes
  std::size_t inverted = 0;                                 ///< elements with signed volume <= 0
  std::size_t degenerate = 0;                               ///< elements with radius ratio < degenerate_radius_ratio
  double degenerate_radius_ratio = kDegenerateRadiusRatio;  ///< the threshold used
  double min_quality = 0.0;                                 ///< smallest radius ratio (0 with no elements)
  double mean_quality = 0.0;                                ///< mean radius ratio
  double min_dihedral_deg = 0.0;                            ///< smallest dihedral angle of all elements
  std::size_t unreferenced_nodes = 0;                       ///< nodes no element uses
  std::size_t out_of_range_indices = 0;                     ///< element node indices outside [0, nodes)

  /// True when there are elements and none is inverted, degenerate or out of range, and
  /// every node is used.
  bool valid() const;
};

/// Counts, volume and quality of a tetrahedral mesh.
TetMeshReport validate_tet_mesh(const TetMesh& mesh, double degenerate_radius_ratio = kDegenerateRadiusRatio);

/// What validate_surface found. Triangles with an out-of-range index are counted there and
/// left out of the edge figures.
struct SurfaceReport {
  std::size_t vertices = 0;
  std::size_t triangles = 0;
  std::size_t boundary_edges = 0;        ///< edges used by one triangle only
  std::size_t non_manifold_edges = 0;    ///< edges used by more than two triangles
  std::size_t inconsistent_edges = 0;    ///< edges two triangles traverse in the same direction
  std::size_t out_of_range_indices = 0;  ///< triangle vertex indices outside [0, vertices)
  bool closed = false;                   ///< triangles exist and every edge has exactly two
  bool consistently_oriented = false;    ///< no edge traversed twice in the same direction
  /// Divergence-theorem volume: meaningful when closed and oriented; 0 with bad indices.
  double enclosed_volume_m3 = 0.0;
};

/// Topology and enclosed volume of a triangulated surface.
SurfaceReport validate_surface(const TriSurface& surface);

/// The boundary of a tetrahedral mesh: its faces used by exactly one element, oriented outward
/// for positively oriented elements, on the mesh nodes they use (in increasing node order).
struct TetMeshBoundary {
  TriSurface surface;
  std::vector<std::int32_t> mesh_node_of_vertex;  ///< surface vertex -> mesh node
};

/// Extracts the boundary surface (elements with out-of-range indices are left out).
TetMeshBoundary extract_boundary(const TetMesh& mesh);

}  // namespace nav
