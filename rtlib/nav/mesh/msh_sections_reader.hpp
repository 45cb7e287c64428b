#pragma once
// Internals shared by the Gmsh .msh 2.2 and 4.1 readers: the state a file builds up section by
// section, node-tag remapping, and the record helpers both versions use. Not a public API.
#include <cstdint>
#include <string_view>
#include <unordered_map>

#include "nav/mesh/tet_mesh.hpp"
#include "nav/mesh/text_lines.hpp"

namespace nav::detail {

/// Gmsh's element type number of the 4-node tetrahedron.
constexpr std::int64_t kMshTetrahedron = 4;

/// What a .msh file has given so far.
struct MshState {
  double metres_per_unit = 1.0;
  TetMesh mesh;
  /// Node tag -> index into mesh.nodes_m (tags may be sparse; looked up, never iterated).
  std::unordered_map<std::int64_t, std::int32_t> node_index_of_tag;
  /// Volume entity tag -> its first physical tag (4.1 $Entities).
  std::unordered_map<std::int64_t, std::int32_t> physical_of_volume;
  bool has_nodes = false;
  bool has_elements = false;
};

/// Reads a count (0 .. 2^31-1) on the current line.
bool read_msh_count(TextScanner& scanner, std::int64_t& count, std::string_view field);

/// Reads the first value of the `index`-th of `count` records; a '$' token there means the
/// section ended early, reported as a wrong count.
bool read_msh_record_start(TextScanner& scanner, std::int64_t& value, std::int64_t index, std::int64_t count,
                           std::string_view field);

/// Reads "x y z" on the current line, scaled to metres.
bool read_msh_point(TextScanner& scanner, double metres_per_unit, Point3& point_m, std::string_view field);

/// Maps node tag `tag` to node index `index`; fails on a duplicate tag.
bool add_msh_node_tag(TextScanner& scanner, std::int64_t tag, std::int32_t index, MshState& state,
                      std::string_view field);

/// Reads the 4 node tags of a tetrahedron on the current line as node indices, then ends the line.
bool read_msh_tet_nodes(TextScanner& scanner, const MshState& state, std::array<std::int32_t, 4>& tet,
                        std::string_view field);

/// Skips the body of a section the readers do not use, through its "$End..." line.
bool skip_msh_section(TextScanner& scanner, std::string_view name);

}  // namespace nav::detail
