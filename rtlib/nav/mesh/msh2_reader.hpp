#pragma once
// The sections of Gmsh .msh ASCII version 2 files ($Nodes, $Elements). Not a public API:
// load_msh_tet_mesh reads the header and calls this for each section.
#include <optional>
#include <string_view>

#include "nav/mesh/msh_sections_reader.hpp"

namespace nav::detail {

/// Reads section `name` (its header token already read) of a version 2 file into `state`;
/// true if read, false on error, nullopt if this version does not use the section.
std::optional<bool> read_msh2_section(TextScanner& scanner, std::string_view name, MshState& state);

}  // namespace nav::detail
