#include "nav/tissue/node_selection.hpp"

namespace nav {

Result<std::vector<std::int32_t>> nodes_in_box(const TetMesh& mesh, const Bounds3& box_m, const std::string& field) {
  std::vector<std::int32_t> nodes;
  for (std::size_t n = 0; n < mesh.nodes_m.size(); ++n) {
    bool inside = true;
    for (int c = 0; c < 3; ++c)
      inside = inside && mesh.nodes_m[n][c] >= box_m.min_m[c] && mesh.nodes_m[n][c] <= box_m.max_m[c];
    if (inside) nodes.push_back(static_cast<std::int32_t>(n));
  }
  if (nodes.empty()) return Error{.message = "the region selects no node", .field = field};
  return nodes;
}

}  // namespace nav
