#pragma once
// Coupling of a frame-based tissue to an organ of any rung (full-order tetrahedral FEM,
// reduced model) through node positions in and nodal forces out: each driven frame is a
// material point of the organ, located at init in one tetrahedron of the organ's rest mesh.
// A coupled step gathers the driven frames' positions from the organ's nodes (barycentric
// mapping), steps the tissue, and returns the tissue's forces on those frames spread over
// the same nodes by the transpose of the mapping (TissueInputs::point_forces), for the organ's
// next step: a staggered (Dirichlet-Neumann) scheme.
//
// Explicit in the coupling force, that scheme diverges as soon as the tissue is stiffer at
// the attachment than the organ's nodes are heavy (k h^2 > m, a few kPa for a liver at
// 100 Hz). It is stabilised by an implicit spring of the tissue's stiffness k_s on each
// attachment node, declared in the organ's scene (TissueScene::spring_nodes, anchored at
// rest), whose force the point forces give back: f = f_tissue(x_n) + k_s (x_n - X). At
// equilibrium the two spring terms cancel; in between, the explicit part is f_tissue + k_s x,
// whose stiffness k - k_s the organ's solve dominates when k_s is about k.
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "nav/connective/frame_tissue_model.hpp"
#include "nav/core/error.hpp"
#include "nav/mesh/tet_mesh.hpp"
#include "nav/tissue/tissue_scene.hpp"

namespace nav {

/// Where the driven frames of a tissue sit in an organ mesh.
struct OrganAttachment {
  std::vector<std::array<std::int32_t, 4>> corners;  ///< the tetrahedron's nodes, per driven frame
  std::vector<std::array<double, 4>> barycentric;    ///< per driven frame, summing to one
  std::vector<std::int32_t> nodes;                   ///< distinct organ nodes that take forces, ascending
  std::vector<std::array<std::int32_t, 4>> slots;    ///< index in `nodes` of each corner
  std::vector<double> node_rest_positions_m;         ///< 3 per entry of `nodes`
  /// The stabilising spring k_s: the largest, over the attachment nodes, of the tissue's
  /// translational stiffness at rest lumped on the node (0: the plain staggered scheme).
  double spring_stiffness_n_m = 0.0;
};

/// The tetrahedron of `mesh` that contains `point_m` (to a relative tolerance of 1e-9 in the
/// barycentric coordinates) and those coordinates; an Error naming `field` when none does.
Result<std::pair<std::int32_t, std::array<double, 4>>> locate_in_tets(const TetMesh& mesh, const Point3& point_m,
                                                                      const std::string& field);

/// Locates every driven frame of `tissue` (at rest) in `organ` and estimates the stabilising
/// spring (zero unless `stabilise`); the Error names the frame outside the organ.
Result<OrganAttachment> attach_driven_frames(const FrameTissueModel& tissue, const TetMesh& organ,
                                             bool stabilise = true);

/// Declares in the organ's scene what the coupling needs: the stabilising springs on the
/// attachment nodes (when k_s > 0) and room for one point force per attachment node beside
/// the scene's other point forces (its max_point_forces grows by their count).
void declare_attachment(const OrganAttachment& attachment, TissueScene& organ_scene);

/// The buffers of one coupled step, sized at init.
struct AttachmentBuffers {
  std::vector<double> driven_positions_m;  ///< 3 per driven frame
  std::vector<PointForce> point_forces;    ///< one per attachment node
};
AttachmentBuffers make_attachment_buffers(const OrganAttachment& attachment);

/// Positions of the driven frames from the organ's node positions (3 per node).
void gather_attachment_positions(const OrganAttachment& attachment, std::span<const double> organ_positions_m,
                                 std::span<double> driven_positions_m) noexcept;

/// The tissue's forces on the driven frames (3 each) spread over the attachment nodes, plus
/// the stabilising spring's k_s (x - X) at the organ positions they were taken at.
void scatter_attachment_forces(const OrganAttachment& attachment, std::span<const double> driven_forces_n,
                               std::span<const double> organ_positions_m, std::span<PointForce> point_forces) noexcept;

/// One staggered step of the tissue: gathers the positions from `organ_positions_m`, steps
/// the tissue and leaves in buffers.point_forces what the organ's next step must take.
void step_attached(const FrameTissueModel& tissue, FrameTissueData& data, const OrganAttachment& attachment,
                   AttachmentBuffers& buffers, std::span<const double> organ_positions_m, double load_scale) noexcept;

}  // namespace nav
