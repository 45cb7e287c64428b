#include "nav/reduced/reduced_basis.hpp"

#include <cstring>

#include "nav/core/fnv_hash.hpp"

namespace nav {

std::uint64_t mesh_fingerprint(const TetMesh& mesh) {
  std::uint64_t hash = kFnvOffsetBasis;
  const std::uint64_t counts[2] = {mesh.nodes_m.size(), mesh.tets.size()};
  hash = fnv1a(hash, counts, sizeof(counts));
  for (const Point3& node : mesh.nodes_m) hash = fnv1a(hash, &node, sizeof(node));
  for (const auto& tet : mesh.tets) hash = fnv1a(hash, tet.data(), sizeof(tet));
  return hash;
}

}  // namespace nav
