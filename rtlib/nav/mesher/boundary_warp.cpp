#include "nav/mesher/boundary_warp.hpp"

#include "nav/mesh/geometry.hpp"
#include "nav/mesher/guarded_node_mover.hpp"

namespace nav {
namespace {

/// A warp is taken whole or not at all.
constexpr int kAllOrNothing = 0;

/// Nodes that need to be on the boundary: those touched by both an inside and an outside
/// element, and those with an edge to a node on the other side of the boundary.
std::vector<std::uint8_t> boundary_candidates(const TetMesh& mesh, const std::vector<std::uint8_t>& inside,
                                              const MeshingDomain& domain) {
  std::vector<std::uint8_t> touches_inside(mesh.nodes_m.size(), 0);
  std::vector<std::uint8_t> touches_outside(mesh.nodes_m.size(), 0);
  for (std::size_t e = 0; e < mesh.tets.size(); ++e)
    for (const std::int32_t n : mesh.tets[e]) (inside[e] ? touches_inside : touches_outside)[n] = 1;
  std::vector<std::uint8_t> side(mesh.nodes_m.size());
  for (std::size_t n = 0; n < mesh.nodes_m.size(); ++n) side[n] = domain.contains(mesh.nodes_m[n]) ? 1 : 0;
  std::vector<std::uint8_t> candidate(mesh.nodes_m.size(), 0);
  for (std::size_t e = 0; e < mesh.tets.size(); ++e) {
    const auto& tet = mesh.tets[e];
    const int sides = side[tet[0]] + side[tet[1]] + side[tet[2]] + side[tet[3]];
    if (sides == 0 || sides == 4) continue;
    for (const std::int32_t n : tet) candidate[n] = 1;
  }
  for (std::size_t n = 0; n < mesh.nodes_m.size(); ++n) candidate[n] |= touches_inside[n] & touches_outside[n];
  return candidate;
}

/// Re-decides the elements around warped nodes: centroid inside, and, if all four nodes were
/// warped onto the boundary, not flat (radius ratio at least the guard's floor).
void reselect(const TetMesh& mesh, std::vector<std::uint8_t>& inside, const MeshingDomain& domain,
              const std::vector<std::uint8_t>& warped, double quality_floor) {
  for (std::size_t e = 0; e < mesh.tets.size(); ++e) {
    const auto& tet = mesh.tets[e];
    const int on_boundary = warped[tet[0]] + warped[tet[1]] + warped[tet[2]] + warped[tet[3]];
    if (on_boundary == 0) continue;
    const Point3& a = mesh.nodes_m[tet[0]];
    const Point3& b = mesh.nodes_m[tet[1]];
    const Point3& c = mesh.nodes_m[tet[2]];
    const Point3& d = mesh.nodes_m[tet[3]];
    const bool flat = on_boundary == 4 && tet_radius_ratio(a, b, c, d) < quality_floor;
    inside[e] = (!flat && domain.contains(0.25 * (a + b + c + d))) ? 1 : 0;
  }
}

}  // namespace

std::size_t warp_to_boundary(TetMesh& mesh, std::vector<std::uint8_t>& inside, const MeshingDomain& domain,
                             const WarpOptions& options) {
  const std::vector<std::uint8_t> candidate = boundary_candidates(mesh, inside, domain);
  GuardedNodeMover mover(mesh);
  std::vector<std::uint8_t> warped(mesh.nodes_m.size(), 0);
  std::size_t moved = 0;
  for (std::size_t n = 0; n < mesh.nodes_m.size(); ++n) {
    if (!candidate[n]) continue;
    const Point3 foot = domain.project_to_boundary(mesh.nodes_m[n]);
    if (norm(foot - mesh.nodes_m[n]) > options.reach_m) continue;
    if (mover.move_towards(static_cast<std::int32_t>(n), foot, options.quality_floor, kAllOrNothing) == 1.0) {
      warped[n] = 1;
      ++moved;
    }
  }
  reselect(mesh, inside, domain, warped, options.quality_floor);
  return moved;
}

}  // namespace nav
