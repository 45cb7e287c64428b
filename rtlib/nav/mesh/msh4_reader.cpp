#include "nav/mesh/msh4_reader.hpp"

#include <algorithm>
#include <limits>
#include <string>

namespace nav::detail {
namespace {

constexpr std::int64_t kInt32Max = std::numeric_limits<std::int32_t>::max();
constexpr std::int64_t kInt32Min = std::numeric_limits<std::int32_t>::min();

/// Reads `count` values on the current line (a section or block header).
template <std::size_t count>
bool read_header(TextScanner& scanner, std::array<std::int64_t, count>& values, std::string_view field) {
  for (std::int64_t& value : values) {
    if (!scanner.read(value, field, Within::line)) return false;
  }
  return scanner.end_line(field);
}

/// Reads a block's record count, which must fit in the `room` records the section header leaves.
bool read_block_size(TextScanner& scanner, std::int64_t room, std::int64_t& block_size, std::string_view field) {
  if (!read_msh_count(scanner, block_size, field)) return false;
  if (block_size <= room) return true;
  return scanner.fail(field, "a block of " + std::to_string(block_size) + " records, but the header leaves room for " +
                                 std::to_string(room));
}

bool check_total(TextScanner& scanner, std::int64_t total, std::int64_t declared, std::string_view field) {
  if (total == declared) return true;
  return scanner.fail(
      field, "blocks hold " + std::to_string(total) + " records, the header declares " + std::to_string(declared));
}

/// A volume entity record: tag, bounding box, physical tags (the first one is kept), surfaces.
bool read_volume_entity(TextScanner& scanner, std::int64_t index, std::int64_t count, MshState& state) {
  std::int64_t tag = 0;
  if (!read_msh_record_start(scanner, tag, index, count, "$Entities")) return false;
  for (int k = 0; k < 6; ++k) {
    double bound = 0.0;
    if (!scanner.read(bound, "$Entities", Within::line)) return false;
  }
  std::int64_t physical_count = 0;
  if (!read_msh_count(scanner, physical_count, "$Entities")) return false;
  if (physical_count > 0) {
    std::int64_t physical = 0;
    if (!scanner.read_in_range(physical, kInt32Min, kInt32Max, "$Entities", Within::line)) return false;
    state.physical_of_volume[tag] = static_cast<std::int32_t>(physical);
  }
  scanner.skip_line();
  return true;
}

bool read_entities(TextScanner& scanner, MshState& state) {
  std::array<std::int64_t, 4> counts{};  // points, curves, surfaces, volumes
  if (!read_header(scanner, counts, "$Entities")) return false;
  if (std::any_of(counts.begin(), counts.end(), [](std::int64_t c) { return c < 0 || c > kInt32Max; })) {
    return scanner.fail("$Entities", "negative or too large entity count");
  }
  const std::int64_t lower_dim_count = counts[0] + counts[1] + counts[2];
  for (std::int64_t i = 0; i < lower_dim_count; ++i) {
    std::int64_t tag = 0;
    if (!read_msh_record_start(scanner, tag, i, lower_dim_count, "$Entities")) return false;
    scanner.skip_line();
  }
  for (std::int64_t i = 0; i < counts[3]; ++i) {
    if (!read_volume_entity(scanner, i, counts[3], state)) return false;
  }
  return scanner.expect("$EndEntities", "$Entities") && scanner.end_line("$Entities");
}

/// One node block: its header, then all its tags, then all its coordinates.
bool read_node_block(TextScanner& scanner, std::int64_t index, std::int64_t count, std::int64_t room, MshState& state,
                     std::int64_t& block_size) {
  std::int64_t dimension = 0;
  std::int64_t entity = 0;
  std::int64_t parametric = 0;
  if (!read_msh_record_start(scanner, dimension, index, count, "$Nodes") ||
      !scanner.read(entity, "$Nodes", Within::line) ||
      !scanner.read_in_range(parametric, 0, 1, "$Nodes", Within::line) ||
      !read_block_size(scanner, room, block_size, "$Nodes") || !scanner.end_line("$Nodes")) {
    return false;
  }
  const auto first_index = static_cast<std::int32_t>(state.mesh.nodes_m.size());
  for (std::int64_t k = 0; k < block_size; ++k) {
    std::int64_t tag = 0;
    if (!read_msh_record_start(scanner, tag, k, block_size, "$Nodes") ||
        !add_msh_node_tag(scanner, tag, first_index + static_cast<std::int32_t>(k), state, "$Nodes") ||
        !scanner.end_line("$Nodes")) {
      return false;
    }
  }
  for (std::int64_t k = 0; k < block_size; ++k) {
    Point3 point_m{};
    if (!read_msh_point(scanner, state.metres_per_unit, point_m, "$Nodes")) return false;
    if (parametric == 1) {
      scanner.skip_line();
    } else if (!scanner.end_line("$Nodes")) {
      return false;
    }
    state.mesh.nodes_m.push_back(point_m);
  }
  return true;
}

bool read_msh4_nodes(TextScanner& scanner, MshState& state) {
  std::array<std::int64_t, 4> header{};  // blocks, nodes, min tag, max tag
  if (!read_header(scanner, header, "$Nodes")) return false;
  if (header[0] < 0 || header[1] < 0 || header[1] > kInt32Max) {
    return scanner.fail("$Nodes", "negative or too large node count");
  }
  state.mesh.nodes_m.reserve(std::min<std::size_t>(static_cast<std::size_t>(header[1]), scanner.remaining() / 8));
  std::int64_t total = 0;
  for (std::int64_t b = 0; b < header[0]; ++b) {
    std::int64_t block_size = 0;
    if (!read_node_block(scanner, b, header[0], header[1] - total, state, block_size)) return false;
    total += block_size;
  }
  return check_total(scanner, total, header[1], "$Nodes") && scanner.expect("$EndNodes", "$Nodes") &&
         scanner.end_line("$Nodes");
}

/// One element block: its header, then one element per line; tetrahedra are kept.
bool read_element_block(TextScanner& scanner, std::int64_t index, std::int64_t count, std::int64_t room,
                        MshState& state, std::int64_t& block_size) {
  std::int64_t dimension = 0;
  std::int64_t entity = 0;
  std::int64_t type = 0;
  if (!read_msh_record_start(scanner, dimension, index, count, "$Elements") ||
      !scanner.read_in_range(entity, kInt32Min, kInt32Max, "$Elements", Within::line) ||
      !scanner.read(type, "$Elements", Within::line) || !read_block_size(scanner, room, block_size, "$Elements") ||
      !scanner.end_line("$Elements")) {
    return false;
  }
  const auto physical = state.physical_of_volume.find(entity);
  const std::int32_t region =
      physical != state.physical_of_volume.end() ? physical->second : static_cast<std::int32_t>(entity);
  for (std::int64_t k = 0; k < block_size; ++k) {
    std::int64_t tag = 0;
    if (!read_msh_record_start(scanner, tag, k, block_size, "$Elements")) return false;
    if (type != kMshTetrahedron) {
      scanner.skip_line();
      continue;
    }
    std::array<std::int32_t, 4> tet{};
    if (!read_msh_tet_nodes(scanner, state, tet, "$Elements")) return false;
    state.mesh.tets.push_back(tet);
    state.mesh.tet_regions.push_back(region);
  }
  return true;
}

bool read_msh4_elements(TextScanner& scanner, MshState& state) {
  std::array<std::int64_t, 4> header{};  // blocks, elements, min tag, max tag
  if (!read_header(scanner, header, "$Elements")) return false;
  if (header[0] < 0 || header[1] < 0) return scanner.fail("$Elements", "negative element count");
  std::int64_t total = 0;
  for (std::int64_t b = 0; b < header[0]; ++b) {
    std::int64_t block_size = 0;
    if (!read_element_block(scanner, b, header[0], header[1] - total, state, block_size)) return false;
    total += block_size;
  }
  return check_total(scanner, total, header[1], "$Elements") && scanner.expect("$EndElements", "$Elements") &&
         scanner.end_line("$Elements");
}

}  // namespace

std::optional<bool> read_msh4_section(TextScanner& scanner, std::string_view name, MshState& state) {
  if (name == "$Entities") return read_entities(scanner, state);
  if (name == "$Nodes") return read_msh4_nodes(scanner, state);
  if (name == "$Elements") return read_msh4_elements(scanner, state);
  return std::nullopt;
}

}  // namespace nav::detail
