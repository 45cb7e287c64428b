#pragma once
// Writes a TetMesh with named point and cell data arrays as an ASCII VTK XML .vtu file that
// ParaView and 3D Slicer open, with doubles in shortest round-trip form (bit-exact on reading
// back). tet_regions, when present, are written as the Int32 cell data array "region".
#include <string>
#include <vector>

#include "nav/core/error.hpp"
#include "nav/mesh/tet_mesh.hpp"

namespace nav {

/// A named data array with `components` values per point or per element, stored point after
/// point (e.g. "displacement_m" with 3 components, "von_mises_stress_pa" with 1).
struct VtuField {
  std::string name;
  int components = 1;
  std::vector<double> values;
};

/// The .vtu text of `mesh` and its fields; an Error if a field's size or name is wrong or an
/// element index is out of range.
Result<std::string> format_vtu(const TetMesh& mesh, const std::vector<VtuField>& point_fields,
                               const std::vector<VtuField>& cell_fields);

/// Writes format_vtu's text to `path`.
Status write_vtu(const std::string& path, const TetMesh& mesh, const std::vector<VtuField>& point_fields = {},
                 const std::vector<VtuField>& cell_fields = {});

}  // namespace nav
