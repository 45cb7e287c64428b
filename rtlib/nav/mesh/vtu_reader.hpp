#pragma once
// VTK XML .vtu (UnstructuredGrid) meshes with format="ascii" DataArrays: Points, Cells
// (connectivity, offsets, types; cell type 10 kept) and the optional cell data array "region"
// (what write_vtu writes for tet_regions). Other arrays and nested elements (InformationKey)
// are skipped; binary, appended or compressed data and multi-piece files are refused with an
// Error naming the file and line (a compressor attribute alone is fine: it applies only to
// binary data).
#include <string>
#include <string_view>

#include "nav/core/error.hpp"
#include "nav/core/units.hpp"
#include "nav/mesh/tet_mesh.hpp"

namespace nav {

/// Name of the cell data array holding TetMesh::tet_regions in .vtu files.
constexpr std::string_view kVtuRegionArray = "region";

/// Loads the tetrahedra of a .vtu file whose coordinates are in `unit`.
Result<TetMesh> load_vtu_tet_mesh(const std::string& path, LengthUnit unit);

/// Parses .vtu text already in memory; `path` only names it in errors.
Result<TetMesh> parse_vtu_tet_mesh(std::string_view text, const std::string& path, LengthUnit unit);

}  // namespace nav
