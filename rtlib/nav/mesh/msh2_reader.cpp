#include "nav/mesh/msh2_reader.hpp"

#include <algorithm>
#include <limits>

namespace nav::detail {
namespace {

constexpr std::int64_t kMaxTagsPerElement = 64;

bool read_msh2_nodes(TextScanner& scanner, MshState& state) {
  std::int64_t count = 0;
  if (!read_msh_count(scanner, count, "$Nodes") || !scanner.end_line("$Nodes")) return false;
  state.mesh.nodes_m.reserve(std::min<std::size_t>(static_cast<std::size_t>(count), scanner.remaining() / 8));
  for (std::int64_t i = 0; i < count; ++i) {
    std::int64_t tag = 0;
    Point3 point_m{};
    const auto index = static_cast<std::int32_t>(state.mesh.nodes_m.size());
    if (!read_msh_record_start(scanner, tag, i, count, "$Nodes") ||
        !add_msh_node_tag(scanner, tag, index, state, "$Nodes") ||
        !read_msh_point(scanner, state.metres_per_unit, point_m, "$Nodes") || !scanner.end_line("$Nodes")) {
      return false;
    }
    state.mesh.nodes_m.push_back(point_m);
  }
  return scanner.expect("$EndNodes", "$Nodes") && scanner.end_line("$Nodes");
}

/// Reads one element record; appends it to the mesh if it is a tetrahedron.
bool read_element(TextScanner& scanner, std::int64_t index, std::int64_t count, MshState& state, bool& has_tags) {
  std::int64_t tag = 0;
  std::int64_t type = 0;
  std::int64_t tag_count = 0;
  if (!read_msh_record_start(scanner, tag, index, count, "$Elements") ||
      !scanner.read(type, "$Elements", Within::line) ||
      !scanner.read_in_range(tag_count, 0, kMaxTagsPerElement, "$Elements", Within::line)) {
    return false;
  }
  if (type != kMshTetrahedron) {
    scanner.skip_line();
    return true;
  }
  std::int64_t region = 0;
  for (std::int64_t k = 0; k < tag_count; ++k) {
    std::int64_t value = 0;
    if (!scanner.read_in_range(value, std::numeric_limits<std::int32_t>::min(),
                               std::numeric_limits<std::int32_t>::max(), "$Elements", Within::line)) {
      return false;
    }
    if (k == 0) region = value;
  }
  has_tags = has_tags || tag_count > 0;
  std::array<std::int32_t, 4> tet{};
  if (!read_msh_tet_nodes(scanner, state, tet, "$Elements")) return false;
  state.mesh.tets.push_back(tet);
  state.mesh.tet_regions.push_back(static_cast<std::int32_t>(region));
  return true;
}

bool read_msh2_elements(TextScanner& scanner, MshState& state) {
  std::int64_t count = 0;
  if (!read_msh_count(scanner, count, "$Elements") || !scanner.end_line("$Elements")) return false;
  bool has_tags = false;
  for (std::int64_t i = 0; i < count; ++i) {
    if (!read_element(scanner, i, count, state, has_tags)) return false;
  }
  if (!has_tags) state.mesh.tet_regions.clear();
  return scanner.expect("$EndElements", "$Elements") && scanner.end_line("$Elements");
}

}  // namespace

std::optional<bool> read_msh2_section(TextScanner& scanner, std::string_view name, MshState& state) {
  if (name == "$Nodes") return read_msh2_nodes(scanner, state);
  if (name == "$Elements") return read_msh2_elements(scanner, state);
  return std::nullopt;
}

}  // namespace nav::detail
