#pragma once
// A uniform grid of boxes over a surface, each listing the triangles whose bounding boxes
// overlap it, so that queries near a point look at a few triangles instead of all of them.
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "nav/mesh/geometry.hpp"

namespace nav {

/// Triangles of a surface binned by bounding box into a grid of cells over `box` (cells
/// along an axis of zero extent: 1, so a grid flat in z serves 2-D queries in x, y).
class TriangleBins {
 public:
  /// Bins every triangle of `surface` into `cells` cells per axis over `box`.
  TriangleBins(const TriSurface& surface, const Bounds3& box, std::array<int, 3> cells);

  /// Cells per axis.
  std::array<int, 3> cells() const { return cells_; }
  /// The box the cells cover.
  const Bounds3& box() const { return box_; }
  /// Edge lengths of one cell (0 along an axis of zero extent).
  const Point3& cell_size_m() const { return cell_size_m_; }

  /// The cell that contains `point_m`, clamped into the grid.
  std::array<int, 3> cell_of(const Point3& point_m) const;

  /// Indices of the triangles that overlap cell (i, j, k), ascending.
  std::span<const std::int32_t> triangles_in(int i, int j, int k) const;

 private:
  int axis_cell(int axis, double coordinate_m) const;

  Bounds3 box_;
  std::array<int, 3> cells_;
  Point3 cell_size_m_{};
  std::vector<std::int32_t> offsets_;
  std::vector<std::int32_t> triangles_;
};

/// Cells per axis for binning `surface` over `box`: cells about twice the mean triangle
/// edge, at most `max_cells_per_axis` along an axis, one along an axis of zero extent.
std::array<int, 3> triangle_bin_counts(const TriSurface& surface, const Bounds3& box, int max_cells_per_axis);

}  // namespace nav
