#pragma once
// Gmsh .msh ASCII meshes, versions 2.2 and 4.1: tetrahedra (element type 4) are kept, other
// elements skipped; node tags may be sparse and are remapped to 0-based indices; the physical
// tag (2.2: first element tag; 4.1: first physical tag of the volume entity, else the entity
// tag) goes to tet_regions.
#include <string>
#include <string_view>

#include "nav/core/error.hpp"
#include "nav/core/units.hpp"
#include "nav/mesh/tet_mesh.hpp"

namespace nav {

/// Loads the tetrahedra of a .msh file whose coordinates are in `unit`.
Result<TetMesh> load_msh_tet_mesh(const std::string& path, LengthUnit unit);

/// Parses .msh text already in memory; `path` only names it in errors.
Result<TetMesh> parse_msh_tet_mesh(std::string_view text, const std::string& path, LengthUnit unit);

}  // namespace nav
