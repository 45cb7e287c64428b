#pragma once
// Wavefront .obj surfaces: 'v' and 'f' records (v, v/vt, v//vn, v/vt/vn, negative indices),
// polygons fan-triangulated; every other record is ignored.
#include <string>
#include <string_view>

#include "nav/core/error.hpp"
#include "nav/core/units.hpp"
#include "nav/mesh/tet_mesh.hpp"

namespace nav {

/// Loads the triangulated surface of an .obj file whose coordinates are in `unit`.
Result<TriSurface> load_obj_surface(const std::string& path, LengthUnit unit);

/// Parses .obj text already in memory; `path` only names it in errors.
Result<TriSurface> parse_obj_surface(std::string_view text, const std::string& path, LengthUnit unit);

}  // namespace nav
