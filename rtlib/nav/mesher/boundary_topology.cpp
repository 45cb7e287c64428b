#include "nav/mesher/boundary_topology.hpp"

#include <algorithm>

#include "nav/mesh/geometry.hpp"
#include "nav/mesh/validation.hpp"

namespace nav {
namespace {

std::pair<std::int32_t, std::int32_t> edge_key(std::int32_t a, std::int32_t b) {
  return a < b ? std::pair{a, b} : std::pair{b, a};
}

std::array<std::int32_t, 3> face_key(std::int32_t a, std::int32_t b, std::int32_t c) {
  std::array<std::int32_t, 3> key{a, b, c};
  std::sort(key.begin(), key.end());
  return key;
}

}  // namespace

BoundaryTopology::BoundaryTopology(const TetMesh& mesh) {
  TetMeshBoundary boundary = extract_boundary(mesh);
  nodes_ = std::move(boundary.mesh_node_of_vertex);
  for (const auto& t : boundary.surface.triangles) {
    const std::int32_t a = nodes_[t[0]];
    const std::int32_t b = nodes_[t[1]];
    const std::int32_t c = nodes_[t[2]];
    faces_.push_back(face_key(a, b, c));
    edges_.insert(edges_.end(), {edge_key(a, b), edge_key(b, c), edge_key(c, a)});
  }
  std::sort(faces_.begin(), faces_.end());
  std::sort(edges_.begin(), edges_.end());
  edges_.erase(std::unique(edges_.begin(), edges_.end()), edges_.end());
}

bool BoundaryTopology::has_node(std::int32_t n) const { return std::binary_search(nodes_.begin(), nodes_.end(), n); }

bool BoundaryTopology::has_edge(std::int32_t a, std::int32_t b) const {
  return std::binary_search(edges_.begin(), edges_.end(), edge_key(a, b));
}

bool BoundaryTopology::has_face(std::int32_t a, std::int32_t b, std::int32_t c) const {
  return std::binary_search(faces_.begin(), faces_.end(), face_key(a, b, c));
}

std::array<bool, 4> BoundaryTopology::faces_of(const std::array<std::int32_t, 4>& tet) const {
  std::array<bool, 4> on{};
  for (int k = 0; k < 4; ++k) on[k] = has_face(tet[kTetFaces[k][0]], tet[kTetFaces[k][1]], tet[kTetFaces[k][2]]);
  return on;
}

}  // namespace nav
