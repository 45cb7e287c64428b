#include "nav/mesh/msh_sections_reader.hpp"

#include <limits>
#include <string>

namespace nav::detail {

bool read_msh_count(TextScanner& scanner, std::int64_t& count, std::string_view field) {
  return scanner.read_in_range(count, 0, std::numeric_limits<std::int32_t>::max(), field, Within::line);
}

bool read_msh_record_start(TextScanner& scanner, std::int64_t& value, std::int64_t index, std::int64_t count,
                           std::string_view field) {
  std::string_view token;
  if (!scanner.read(token, field)) return false;
  if (token.starts_with('$')) {
    return scanner.fail(field, "found '" + std::string(token) + "' after " + std::to_string(index) + " of " +
                                   std::to_string(count) + " records");
  }
  const auto parsed = parse_int(token);
  if (!parsed) return scanner.fail(field, "'" + std::string(token) + "' is not an integer");
  value = *parsed;
  return true;
}

bool read_msh_point(TextScanner& scanner, double metres_per_unit, Point3& point_m, std::string_view field) {
  for (double& coordinate : point_m) {
    if (!scanner.read(coordinate, field, Within::line)) return false;
    coordinate *= metres_per_unit;
  }
  return true;
}

bool add_msh_node_tag(TextScanner& scanner, std::int64_t tag, std::int32_t index, MshState& state,
                      std::string_view field) {
  if (state.node_index_of_tag.emplace(tag, index).second) return true;
  return scanner.fail(field, "duplicate node tag " + std::to_string(tag));
}

bool read_msh_tet_nodes(TextScanner& scanner, const MshState& state, std::array<std::int32_t, 4>& tet,
                        std::string_view field) {
  for (std::int32_t& node : tet) {
    std::int64_t tag = 0;
    if (!scanner.read(tag, field, Within::line)) return false;
    const auto found = state.node_index_of_tag.find(tag);
    if (found == state.node_index_of_tag.end()) {
      return scanner.fail(field, "node tag " + std::to_string(tag) + " is not in $Nodes");
    }
    node = found->second;
  }
  return scanner.end_line(field);
}

bool skip_msh_section(TextScanner& scanner, std::string_view name) {
  const std::string end_marker = "$End" + std::string(name.substr(1));
  while (!scanner.at_end()) {
    std::string_view token;
    scanner.read(token, name, Within::line);
    if (token == end_marker) return scanner.end_line(name);
    scanner.skip_line();
  }
  return scanner.fail(name, "unexpected end of file before " + end_marker);
}

}  // namespace nav::detail
