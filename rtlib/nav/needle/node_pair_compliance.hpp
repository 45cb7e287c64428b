#pragma once
// A sparse table of 3x3 compliances between nearby tissue nodes: what a reduced tissue misses
// of the full order's response between the nodes a needle's constraint points sit on
// (missing_node_compliance()). Plain data; lookups allocate nothing.
#include <algorithm>
#include <cstdint>
#include <vector>

namespace nav {

/// Per node a, its entries from starts[a] to starts[a + 1]: a node b (ascending, a itself
/// among them) and the 3x3 block, row-major, of a's displacement per newton on b (m/N).
/// Empty: no node has any.
struct NodePairCompliance {
  std::vector<std::int32_t> starts;
  std::vector<std::int32_t> nodes;
  std::vector<double> blocks_m_per_n;  ///< 9 per entry

  /// The block of (a, b), or nullptr when the table holds none.
  const double* find(std::int32_t a, std::int32_t b) const noexcept {
    if (a < 0 || static_cast<std::size_t>(a) + 1 >= starts.size()) return nullptr;
    const auto first = nodes.begin() + starts[static_cast<std::size_t>(a)];
    const auto last = nodes.begin() + starts[static_cast<std::size_t>(a) + 1];
    const auto at = std::lower_bound(first, last, b);
    return at != last && *at == b ? blocks_m_per_n.data() + 9 * static_cast<std::size_t>(at - nodes.begin()) : nullptr;
  }
};

}  // namespace nav
