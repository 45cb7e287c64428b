#include "nav/mesh/vtk_grid_reader.hpp"

#include <algorithm>
#include <limits>
#include <utility>

#include "nav/mesh/text_lines.hpp"

namespace nav::detail {

template <typename T>
Error VtkArray<T>::error_at(const std::string& path, std::size_t index, std::string message) const {
  return Error{
      .message = std::move(message), .file = path, .line = line_of_token(text, first_line, index), .field = field};
}

template struct VtkArray<double>;
template struct VtkArray<std::int64_t>;

Result<std::vector<VtkCellSpan>> cell_spans_from_offsets(const VtkArray<std::int64_t>& offsets, bool leading_zero,
                                                         std::size_t connectivity_size, const std::string& path) {
  const auto& values = offsets.values;
  if (leading_zero && (values.empty() || values.front() != 0)) {
    return offsets.error_at(path, 0, "offsets must start with 0");
  }
  const auto size = static_cast<std::int64_t>(connectivity_size);
  std::vector<VtkCellSpan> spans;
  spans.reserve(values.size());
  std::int64_t begin = 0;
  for (std::size_t i = leading_zero ? 1 : 0; i < values.size(); ++i) {
    const std::int64_t end = values[i];
    if (end < begin) return offsets.error_at(path, i, "offset " + std::to_string(end) + " is below the previous one");
    if (end > size) {
      return offsets.error_at(
          path, i, "offset " + std::to_string(end) + " is beyond the " + std::to_string(size) + " connectivity values");
    }
    spans.push_back({begin, end});
    begin = end;
  }
  if (begin != size) {
    return offsets.error_at(
        path, values.size(),
        "the offsets cover " + std::to_string(begin) + " of the " + std::to_string(size) + " connectivity values");
  }
  return spans;
}

Result<std::vector<VtkCellSpan>> cell_spans_from_counts(const VtkArray<std::int64_t>& cells, std::size_t cell_count,
                                                        const std::string& path) {
  const auto size = static_cast<std::int64_t>(cells.values.size());
  std::vector<VtkCellSpan> spans;
  spans.reserve(std::min(cell_count, cells.values.size()));  // a cell takes one value at least
  std::int64_t position = 0;
  for (std::size_t c = 0; c < cell_count; ++c) {
    if (position >= size) {
      return cells.error_at(
          path, cells.values.size(),
          "the data ends after " + std::to_string(c) + " of " + std::to_string(cell_count) + " cells");
    }
    const std::int64_t count = cells.values[static_cast<std::size_t>(position)];
    if (count < 0 || count >= size - position) {
      return cells.error_at(
          path, static_cast<std::size_t>(position),
          "cell " + std::to_string(c) + " claims " + std::to_string(count) + " points, more than the data left");
    }
    spans.push_back({position + 1, position + 1 + count});
    position += 1 + count;
  }
  if (position != size) {
    return cells.error_at(path, static_cast<std::size_t>(position),
                          std::to_string(size - position) + " values left after the last cell");
  }
  return spans;
}

Result<TetMesh> tet_mesh_from_vtk_grid(const VtkGridArrays& grid, const std::string& path, double metres_per_unit) {
  const std::size_t cell_count = grid.cells.size();
  if (grid.types.values.size() != cell_count) {
    return grid.types.error_at(
        path, std::min(cell_count, grid.types.values.size()),
        std::to_string(grid.types.values.size()) + " cell types for " + std::to_string(cell_count) + " cells");
  }
  const bool has_regions = !grid.regions.values.empty();
  if (has_regions && grid.regions.values.size() != cell_count) {
    return grid.regions.error_at(
        path, std::min(cell_count, grid.regions.values.size()),
        std::to_string(grid.regions.values.size()) + " region tags for " + std::to_string(cell_count) + " cells");
  }
  TetMesh mesh;
  const std::size_t point_count = grid.points.values.size() / 3;
  mesh.nodes_m.resize(point_count);
  for (std::size_t p = 0; p < point_count; ++p) {
    for (std::size_t k = 0; k < 3; ++k) mesh.nodes_m[p][k] = grid.points.values[3 * p + k] * metres_per_unit;
  }
  for (std::size_t c = 0; c < cell_count; ++c) {
    if (grid.types.values[c] != kVtkTetra) continue;
    const VtkCellSpan span = grid.cells[c];
    if (span.end - span.begin != 4) {
      return grid.types.error_at(
          path, c,
          "cell " + std::to_string(c) + " of type 10 has " + std::to_string(span.end - span.begin) + " points, not 4");
    }
    std::array<std::int32_t, 4> tet{};
    for (std::size_t k = 0; k < 4; ++k) {
      const auto at = static_cast<std::size_t>(span.begin) + k;
      const std::int64_t index = grid.connectivity.values[at];
      if (index < 0 || index >= static_cast<std::int64_t>(point_count)) {
        return grid.connectivity.error_at(
            path, at,
            "point index " + std::to_string(index) + " is out of range (" + std::to_string(point_count) + " points)");
      }
      tet[k] = static_cast<std::int32_t>(index);
    }
    mesh.tets.push_back(tet);
    if (!has_regions) continue;
    const std::int64_t region = grid.regions.values[c];
    if (region < std::numeric_limits<std::int32_t>::min() || region > std::numeric_limits<std::int32_t>::max()) {
      return grid.regions.error_at(path, c, "region tag " + std::to_string(region) + " does not fit 32 bits");
    }
    mesh.tet_regions.push_back(static_cast<std::int32_t>(region));
  }
  if (mesh.tets.empty()) {
    return grid.types.error_at(path, grid.types.values.size(), "no tetrahedra (cell type 10)");
  }
  return mesh;
}

}  // namespace nav::detail
