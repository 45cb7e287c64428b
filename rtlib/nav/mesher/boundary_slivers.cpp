#include "nav/mesher/boundary_slivers.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include "nav/mesh/geometry.hpp"
#include "nav/mesher/boundary_topology.hpp"
#include "nav/mesher/crease.hpp"
#include "nav/mesher/mesh_subset.hpp"

namespace nav {
namespace {

constexpr int kMaxRounds = 8;

/// True if `tet`, all of whose nodes are on the boundary, is a ridge or a cap (`faces`: which
/// of its faces are on the boundary).
bool sticks_out(const std::array<std::int32_t, 4>& tet, const std::array<bool, 4>& faces,
                const BoundaryTopology& boundary) {
  const auto on_boundary = std::count(faces.begin(), faces.end(), true);
  if (on_boundary != 2) return on_boundary > 2;
  // Face k is opposite node k: the two interior faces share the edge between the two nodes
  // whose opposite faces are on the boundary. If that edge were on the boundary already, the
  // removal would leave it with four boundary faces.
  std::array<std::int32_t, 2> shared{};
  int found = 0;
  for (int k = 0; k < 4; ++k)
    if (faces[k]) shared[found++] = tet[k];
  return !boundary.has_edge(shared[0], shared[1]);
}

/// True if `tet` lies on an edge or corner of the domain: its nodes on the domain's boundary
/// (within `tolerance_m`) and two of its boundary faces bending by more than the crease angle
/// (cosine of their normals below `crease_cosine`).
bool on_domain_crease(const TetMesh& mesh, const std::array<std::int32_t, 4>& tet, const std::array<bool, 4>& faces,
                      const MeshingDomain& domain, double crease_cosine, double tolerance_m) {
  for (const std::int32_t n : tet) {
    if (norm(domain.project_to_boundary(mesh.nodes_m[n]) - mesh.nodes_m[n]) > tolerance_m) return false;
  }
  std::vector<Point3> normals;
  for (int k = 0; k < 4; ++k) {
    if (!faces[k]) continue;
    const Point3& a = mesh.nodes_m[tet[kTetFaces[k][0]]];
    normals.push_back(cross(mesh.nodes_m[tet[kTetFaces[k][1]]] - a, mesh.nodes_m[tet[kTetFaces[k][2]]] - a));
  }
  return bends_into_crease(normals, crease_cosine);
}

/// One sweep: removes the ridges and caps of `mesh` as it is; returns how many.
std::size_t remove_once(TetMesh& mesh, const MeshingDomain& domain, const SliverOptions& options) {
  const BoundaryTopology boundary(mesh);
  std::vector<std::uint8_t> keep(mesh.tets.size(), 1);
  std::size_t removed = 0;
  for (std::size_t e = 0; e < mesh.tets.size(); ++e) {
    const auto& tet = mesh.tets[e];
    const bool all_on_boundary =
        std::all_of(tet.begin(), tet.end(), [&](std::int32_t n) { return boundary.has_node(n); });
    if (!all_on_boundary) continue;
    const auto faces = boundary.faces_of(tet);
    if (!sticks_out(tet, faces, boundary) ||
        on_domain_crease(mesh, tet, faces, domain, options.crease_cosine, options.tolerance_m)) {
      continue;
    }
    keep[e] = 0;
    ++removed;
  }
  if (removed > 0) mesh = mesh_subset(mesh, keep);
  return removed;
}

}  // namespace

std::size_t remove_boundary_slivers(TetMesh& mesh, const MeshingDomain& domain, const SliverOptions& options) {
  std::size_t removed = 0;
  for (int round = 0; round < kMaxRounds; ++round) {
    const std::size_t once = remove_once(mesh, domain, options);
    if (once == 0) break;
    removed += once;
  }
  return removed;
}

}  // namespace nav
