#include "nav/mesher/mesh_subset.hpp"

namespace nav {

TetMesh mesh_subset(const TetMesh& mesh, const std::vector<std::uint8_t>& keep) {
  std::vector<std::int32_t> new_index(mesh.nodes_m.size(), -1);
  for (std::size_t e = 0; e < mesh.tets.size(); ++e)
    if (keep[e])
      for (const std::int32_t n : mesh.tets[e]) new_index[n] = 0;
  TetMesh subset;
  for (std::size_t n = 0; n < mesh.nodes_m.size(); ++n) {
    if (new_index[n] < 0) continue;
    new_index[n] = static_cast<std::int32_t>(subset.nodes_m.size());
    subset.nodes_m.push_back(mesh.nodes_m[n]);
  }
  for (std::size_t e = 0; e < mesh.tets.size(); ++e) {
    if (!keep[e]) continue;
    const auto& tet = mesh.tets[e];
    subset.tets.push_back({new_index[tet[0]], new_index[tet[1]], new_index[tet[2]], new_index[tet[3]]});
    if (!mesh.tet_regions.empty()) subset.tet_regions.push_back(mesh.tet_regions[e]);
  }
  return subset;
}

}  // namespace nav
