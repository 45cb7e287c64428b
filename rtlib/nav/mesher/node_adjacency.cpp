#include "nav/mesher/node_adjacency.hpp"

#include <algorithm>

namespace nav {

namespace {

/// Compressed lists of the items (elements, faces) that use each node.
template <std::size_t corners>
NodeLists users_of_nodes(const std::vector<std::array<std::int32_t, corners>>& items, std::size_t node_count) {
  NodeLists lists;
  lists.offsets.assign(node_count + 1, 0);
  for (const auto& item : items)
    for (const std::int32_t n : item) ++lists.offsets[n + 1];
  for (std::size_t n = 0; n < node_count; ++n) lists.offsets[n + 1] += lists.offsets[n];
  lists.items.resize(static_cast<std::size_t>(lists.offsets.back()));
  std::vector<std::int32_t> fill(lists.offsets.begin(), lists.offsets.end() - 1);
  for (std::size_t i = 0; i < items.size(); ++i)
    for (const std::int32_t n : items[i]) lists.items[fill[n]++] = static_cast<std::int32_t>(i);
  return lists;
}

}  // namespace

NodeLists elements_of_nodes(const TetMesh& mesh) { return users_of_nodes(mesh.tets, mesh.nodes_m.size()); }

NodeLists faces_of_nodes(const std::vector<std::array<std::int32_t, 3>>& faces, std::size_t node_count) {
  return users_of_nodes(faces, node_count);
}

NodeLists neighbours_of_nodes(const TetMesh& mesh) {
  const NodeLists elements = elements_of_nodes(mesh);
  NodeLists lists;
  lists.offsets.assign(mesh.nodes_m.size() + 1, 0);
  std::vector<std::int32_t> scratch;
  for (std::size_t n = 0; n < mesh.nodes_m.size(); ++n) {
    scratch.clear();
    for (const std::int32_t e : elements.of(static_cast<std::int32_t>(n)))
      for (const std::int32_t m : mesh.tets[e])
        if (m != static_cast<std::int32_t>(n)) scratch.push_back(m);
    std::sort(scratch.begin(), scratch.end());
    scratch.erase(std::unique(scratch.begin(), scratch.end()), scratch.end());
    lists.items.insert(lists.items.end(), scratch.begin(), scratch.end());
    lists.offsets[n + 1] = static_cast<std::int32_t>(lists.items.size());
  }
  return lists;
}

}  // namespace nav
