#include "nav/reduced/reduced_basis.hpp"

#include <cstring>

namespace nav {
namespace {

constexpr std::uint64_t kFnvOffset = 14695981039346656037ull;
constexpr std::uint64_t kFnvPrime = 1099511628211ull;

std::uint64_t fnv1a(std::uint64_t hash, const void* bytes, std::size_t size) {
  const auto* byte = static_cast<const unsigned char*>(bytes);
  for (std::size_t i = 0; i < size; ++i) {
    hash ^= byte[i];
    hash *= kFnvPrime;
  }
  return hash;
}

}  // namespace

std::uint64_t mesh_fingerprint(const TetMesh& mesh) {
  std::uint64_t hash = kFnvOffset;
  const std::uint64_t counts[2] = {mesh.nodes_m.size(), mesh.tets.size()};
  hash = fnv1a(hash, counts, sizeof(counts));
  for (const Point3& node : mesh.nodes_m) hash = fnv1a(hash, &node, sizeof(node));
  for (const auto& tet : mesh.tets) hash = fnv1a(hash, tet.data(), sizeof(tet));
  return hash;
}

}  // namespace nav
