#include "nav/mesh/msh_reader.hpp"

#include <string>

#include "nav/mesh/msh2_reader.hpp"
#include "nav/mesh/msh4_reader.hpp"

namespace nav {
namespace {

using detail::MshState;

enum class MshVersion { v2, v4 };

/// Reads "$MeshFormat / version file-type data-size / $EndMeshFormat".
bool read_mesh_format(TextScanner& scanner, MshVersion& version) {
  std::string_view number;
  std::int64_t file_type = 0;
  std::int64_t data_size = 0;
  if (!scanner.expect("$MeshFormat", "$MeshFormat") || !scanner.end_line("$MeshFormat") ||
      !scanner.read(number, "$MeshFormat")) {
    return false;
  }
  if (number == "2" || number == "2.0" || number == "2.1" || number == "2.2") {
    version = MshVersion::v2;
  } else if (number == "4.1") {
    version = MshVersion::v4;
  } else {
    return scanner.fail("$MeshFormat", "unsupported version '" + std::string(number) + "' (2.2 and 4.1 are read)");
  }
  if (!scanner.read(file_type, "$MeshFormat", Within::line)) return false;
  if (file_type != 0) return scanner.fail("$MeshFormat", "binary .msh files are not supported (file-type 1)");
  return scanner.read(data_size, "$MeshFormat", Within::line) && scanner.end_line("$MeshFormat") &&
         scanner.expect("$EndMeshFormat", "$MeshFormat") && scanner.end_line("$MeshFormat");
}

/// Reads one section (its name just read) of a version `version` file, checking that $Nodes
/// and $Elements come once, in that order.
bool read_section(TextScanner& scanner, std::string_view name, MshVersion version, MshState& state) {
  const bool is_nodes = name == "$Nodes";
  const bool is_elements = name == "$Elements";
  if ((is_nodes && state.has_nodes) || (is_elements && state.has_elements)) {
    return scanner.fail(name, "second " + std::string(name) + " section");
  }
  if (is_elements && !state.has_nodes) return scanner.fail(name, "$Elements comes before $Nodes");
  if (!scanner.end_line(name)) return false;
  const auto read = version == MshVersion::v2 ? detail::read_msh2_section(scanner, name, state)
                                              : detail::read_msh4_section(scanner, name, state);
  if (!read) return detail::skip_msh_section(scanner, name);
  state.has_nodes = state.has_nodes || is_nodes;
  state.has_elements = state.has_elements || is_elements;
  return *read;
}

}  // namespace

Result<TetMesh> parse_msh_tet_mesh(std::string_view text, const std::string& path, LengthUnit unit) {
  TextScanner scanner(path, text);
  MshVersion version = MshVersion::v2;
  if (!read_mesh_format(scanner, version)) return scanner.error();
  MshState state;
  state.metres_per_unit = metres_per_unit(unit);
  while (!scanner.at_end()) {
    std::string_view name;
    scanner.read(name, "section", Within::line);
    if (!name.starts_with('$')) {
      scanner.fail("section", "expected a section name ($...), found '" + std::string(name) + "'");
      return scanner.error();
    }
    if (!read_section(scanner, name, version, state)) return scanner.error();
  }
  if (!state.has_nodes) scanner.fail("$Nodes", "missing $Nodes section");
  if (!state.has_elements) scanner.fail("$Elements", "missing $Elements section");
  if (state.mesh.tets.empty()) scanner.fail("$Elements", "no tetrahedra (element type 4)");
  if (!state.has_nodes || !state.has_elements || state.mesh.tets.empty()) return scanner.error();
  return std::move(state.mesh);
}

Result<TetMesh> load_msh_tet_mesh(const std::string& path, LengthUnit unit) {
  auto text = read_text_file(path);
  if (!text) return text.error();
  return parse_msh_tet_mesh(text.value(), path, unit);
}

}  // namespace nav
