#pragma once
// Internals shared by the VTK legacy (.vtk) and XML (.vtu) readers: the arrays of an
// unstructured grid as read from the file, and their assembly into a TetMesh (cell type 10
// kept, others skipped), with every fault located at the line of the faulty value.
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "nav/core/error.hpp"
#include "nav/mesh/tet_mesh.hpp"

namespace nav::detail {

/// VTK's cell type number of the 4-node linear tetrahedron.
constexpr std::int64_t kVtkTetra = 10;

/// The numbers of one array of a VTK file, with the text they came from so that a value
/// found faulty later can be located.
template <typename T>
struct VtkArray {
  std::vector<T> values;
  std::string_view text;  ///< the array's text in the file
  int first_line = 0;     ///< the file line on which `text` starts
  std::string field;      ///< the array's name in errors ("POINTS", "connectivity")

  /// An Error located at the value of index `index` (at the array's last value if beyond it).
  Error error_at(const std::string& path, std::size_t index, std::string message) const;
};

/// Where one cell's point indices are in the connectivity array: [begin, end).
struct VtkCellSpan {
  std::int64_t begin = 0;
  std::int64_t end = 0;
};

/// The arrays of an unstructured grid as a reader found them.
struct VtkGridArrays {
  VtkArray<double> points;              ///< x y z per point, in the file's unit
  VtkArray<std::int64_t> connectivity;  ///< point indices (legacy: with each cell's count first)
  std::vector<VtkCellSpan> cells;       ///< one span of connectivity per cell
  VtkArray<std::int64_t> types;         ///< one VTK cell type per cell
  VtkArray<std::int64_t> regions;       ///< one region tag per cell, or empty
};

/// Cell spans from offsets: VTU's one end offset per cell (`leading_zero` false) or legacy
/// 5.1's cell count + 1 offsets beginning with 0 (`leading_zero` true).
Result<std::vector<VtkCellSpan>> cell_spans_from_offsets(const VtkArray<std::int64_t>& offsets, bool leading_zero,
                                                         std::size_t connectivity_size, const std::string& path);

/// Cell spans of legacy (before 5.1) CELLS data, where each cell is its point count then its points.
Result<std::vector<VtkCellSpan>> cell_spans_from_counts(const VtkArray<std::int64_t>& cells, std::size_t cell_count,
                                                        const std::string& path);

/// The tetrahedra of the grid, coordinates scaled to metres.
Result<TetMesh> tet_mesh_from_vtk_grid(const VtkGridArrays& grid, const std::string& path, double metres_per_unit);

}  // namespace nav::detail
