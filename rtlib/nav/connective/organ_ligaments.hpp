#pragma once
// Ligaments that hang an organ from a fixed wall above it (+z): blocks of frames whose lowest
// layer lies just inside the organ's upper surface (driven by the organ through an
// OrganAttachment) and whose highest layer is fixed. Init-time code.
#include <array>
#include <vector>

#include "nav/connective/organ_attachment.hpp"

namespace nav {

/// One ligament block: a footprint on the organ's upper surface and a length up to the wall.
struct LigamentSpec {
  Point3 footprint_centre_m{};  ///< x and y are used
  double width_m = 0.03;        ///< along x
  double depth_m = 0.03;        ///< along y
  double length_m = 0.03;       ///< from the lowest layer to the wall, along z
  std::array<int, 3> frames{3, 3, 3};
  /// Depth of the lowest layer under the organ's upper surface (the lowest, over the
  /// footprint's columns, of the highest node near each column).
  double embed_m = 0.004;
};

/// The ligaments of an organ, solved as one frame-based tissue, and their attachment.
struct OrganLigaments {
  FrameTissueModel model;
  OrganAttachment attachment;
  std::vector<FrameGrid> grids;  ///< one per ligament, in LigamentSpec order
};

/// Builds the ligaments of `specs` on `organ` (with the stabilising spring unless `stabilise`
/// is false); the Error names the ligament whose footprint finds no organ or whose lowest
/// layer leaves it.
Result<OrganLigaments> make_organ_ligaments(const TetMesh& organ, const std::vector<LigamentSpec>& specs,
                                            const ElasticMaterial& material, const FrameTissueOptions& options,
                                            const Point3& gravity_m_s2, bool stabilise = true);

}  // namespace nav
