#pragma once
// The embedded default liver: a procedural liver with a tumour and its attachments, meshed by
// the library's own mesher, for demos and tests when no patient mesh is given.
#include <cstdint>
#include <vector>

#include "nav/mesh/tet_mesh.hpp"

namespace nav {

/// A ready-to-simulate liver (frame and shape: see liver_shape.hpp; about 1.5 L). Elements
/// whose centroid is in the tumour's ball are tagged TissueRegion::tumour, the others
/// parenchyma.
struct EmbeddedLiver {
  TetMesh mesh;
  Point3 tumour_centre_m;  ///< the target point, deep in the right lobe
  double tumour_radius_m;
  /// Boundary nodes held by the surroundings, ascending: the hilum (centre of the visceral
  /// surface), the falciform ligament (over the top between the lobes) and the coronary
  /// ligament (along the posterior top edge).
  std::vector<std::int32_t> attachment_nodes;
};

/// The element size (metres) that gives about 5000 tetrahedra.
inline constexpr double kEmbeddedLiverElementSizeM = 0.012;

/// Meshes the embedded liver at `element_size_m` (see make_tet_mesh) and places its tumour
/// and attachments. Deterministic. Throws std::invalid_argument if the size cannot mesh it
/// (not positive, or so small that the grid would exceed 2^24 cubes).
EmbeddedLiver make_embedded_liver(double element_size_m);

}  // namespace nav
