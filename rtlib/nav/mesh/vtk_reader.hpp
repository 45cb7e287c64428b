#pragma once
// VTK legacy .vtk ASCII UNSTRUCTURED_GRID meshes (the classic CELLS layout and 5.1's
// OFFSETS/CONNECTIVITY layout): POINTS, CELLS and CELL_TYPES are read, cell type 10
// (tetrahedron) kept; FIELD and METADATA blocks are skipped, attribute data
// (POINT_DATA, CELL_DATA) ignored.
#include <string>
#include <string_view>

#include "nav/core/error.hpp"
#include "nav/core/units.hpp"
#include "nav/mesh/tet_mesh.hpp"

namespace nav {

/// Loads the tetrahedra of a legacy .vtk file whose coordinates are in `unit`.
Result<TetMesh> load_vtk_tet_mesh(const std::string& path, LengthUnit unit);

/// Parses legacy .vtk text already in memory; `path` only names it in errors.
Result<TetMesh> parse_vtk_tet_mesh(std::string_view text, const std::string& path, LengthUnit unit);

}  // namespace nav
