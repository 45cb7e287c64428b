#include "nav/mesher/triangle_bins.hpp"

#include <algorithm>
#include <cmath>

namespace nav {

TriangleBins::TriangleBins(const TriSurface& surface, const Bounds3& box, std::array<int, 3> cells)
    : box_(box), cells_(cells) {
  for (int a = 0; a < 3; ++a) {
    cells_[a] = std::max(cells_[a], 1);
    cell_size_m_[a] = (box_.max_m[a] - box_.min_m[a]) / cells_[a];
  }
  const std::size_t cell_count = static_cast<std::size_t>(cells_[0]) * cells_[1] * cells_[2];
  // Two sweeps over the triangles: count per cell, then fill (compressed row storage).
  std::vector<std::array<int, 6>> ranges(surface.triangles.size());
  std::vector<std::int32_t> counts(cell_count + 1, 0);
  for (std::size_t t = 0; t < surface.triangles.size(); ++t) {
    const auto& tri = surface.triangles[t];
    for (int a = 0; a < 3; ++a) {
      const double lo =
          std::min({surface.vertices_m[tri[0]][a], surface.vertices_m[tri[1]][a], surface.vertices_m[tri[2]][a]});
      const double hi =
          std::max({surface.vertices_m[tri[0]][a], surface.vertices_m[tri[1]][a], surface.vertices_m[tri[2]][a]});
      ranges[t][a] = axis_cell(a, lo);
      ranges[t][a + 3] = axis_cell(a, hi);
    }
    const auto& r = ranges[t];
    for (int k = r[2]; k <= r[5]; ++k)
      for (int j = r[1]; j <= r[4]; ++j)
        for (int i = r[0]; i <= r[3]; ++i) ++counts[1 + i + static_cast<std::size_t>(cells_[0]) * (j + cells_[1] * k)];
  }
  offsets_.assign(cell_count + 1, 0);
  for (std::size_t c = 0; c < cell_count; ++c) offsets_[c + 1] = offsets_[c] + counts[c + 1];
  triangles_.resize(static_cast<std::size_t>(offsets_[cell_count]));
  std::vector<std::int32_t> fill(offsets_.begin(), offsets_.end() - 1);
  for (std::size_t t = 0; t < surface.triangles.size(); ++t) {
    const auto& r = ranges[t];
    for (int k = r[2]; k <= r[5]; ++k)
      for (int j = r[1]; j <= r[4]; ++j)
        for (int i = r[0]; i <= r[3]; ++i)
          triangles_[fill[i + static_cast<std::size_t>(cells_[0]) * (j + cells_[1] * k)]++] =
              static_cast<std::int32_t>(t);
  }
}

int TriangleBins::axis_cell(int axis, double coordinate_m) const {
  if (!(cell_size_m_[axis] > 0.0)) return 0;
  const double u = std::floor((coordinate_m - box_.min_m[axis]) / cell_size_m_[axis]);
  return static_cast<int>(std::clamp(u, 0.0, static_cast<double>(cells_[axis] - 1)));
}

std::array<int, 3> TriangleBins::cell_of(const Point3& point_m) const {
  return {axis_cell(0, point_m[0]), axis_cell(1, point_m[1]), axis_cell(2, point_m[2])};
}

std::span<const std::int32_t> TriangleBins::triangles_in(int i, int j, int k) const {
  const std::size_t c = i + static_cast<std::size_t>(cells_[0]) * (j + cells_[1] * k);
  return {triangles_.data() + offsets_[c], static_cast<std::size_t>(offsets_[c + 1] - offsets_[c])};
}

std::array<int, 3> triangle_bin_counts(const TriSurface& surface, const Bounds3& box, int max_cells_per_axis) {
  double edge_sum_m = 0.0;
  for (const auto& tri : surface.triangles) {
    for (int e = 0; e < 3; ++e) edge_sum_m += norm(surface.vertices_m[tri[(e + 1) % 3]] - surface.vertices_m[tri[e]]);
  }
  const double edges = 3.0 * static_cast<double>(std::max<std::size_t>(surface.triangles.size(), 1));
  const double cell_m = 2.0 * edge_sum_m / edges;
  std::array<int, 3> cells{1, 1, 1};
  for (int a = 0; a < 3; ++a) {
    const double extent_m = box.max_m[a] - box.min_m[a];
    if (extent_m > 0.0 && cell_m > 0.0) {
      cells[a] =
          static_cast<int>(std::clamp(std::ceil(extent_m / cell_m), 1.0, static_cast<double>(max_cells_per_axis)));
    }
  }
  return cells;
}

}  // namespace nav
