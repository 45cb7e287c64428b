#include "nav/connective/frame_layout.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "nav/mesh/geometry.hpp"

namespace nav {
namespace {

/// Gauss-Legendre abscissae and weights on [0, 1], n = 1 to 4.
void gauss_rule(int n, std::vector<double>& x, std::vector<double>& w) {
  static const double x2 = 0.5 / std::sqrt(3.0), x3 = 0.5 * std::sqrt(0.6);
  const double a4 = 0.5 * std::sqrt(3.0 / 7.0 - 2.0 / 7.0 * std::sqrt(1.2)),
               b4 = 0.5 * std::sqrt(3.0 / 7.0 + 2.0 / 7.0 * std::sqrt(1.2));
  const double wa4 = (18.0 + std::sqrt(30.0)) / 72.0, wb4 = (18.0 - std::sqrt(30.0)) / 72.0;
  switch (n) {
    case 1:
      x = {0.5};
      w = {1.0};
      break;
    case 2:
      x = {0.5 - x2, 0.5 + x2};
      w = {0.5, 0.5};
      break;
    case 3:
      x = {0.5 - x3, 0.5, 0.5 + x3};
      w = {5.0 / 18.0, 8.0 / 18.0, 5.0 / 18.0};
      break;
    default:
      x = {0.5 - b4, 0.5 - a4, 0.5 + a4, 0.5 + b4};
      w = {wb4, wa4, wa4, wb4};
      break;
  }
}

/// Frames (grid indices), weights and gradients of the tensor-product shape functions at a
/// point given in grid coordinates u (metres along each axis from the origin).
void shape_functions(const FrameGrid& grid, const Point3& u, PointNeighbours& out) {
  std::array<std::array<int, 2>, 3> index{};
  std::array<std::array<double, 2>, 3> value{}, slope{};
  std::array<int, 3> terms{};
  for (int d = 0; d < 3; ++d) {
    if (grid.counts[d] == 1) {
      index[d] = {0, 0};
      value[d] = {1.0, 0.0};
      slope[d] = {0.0, 0.0};
      terms[d] = 1;
      continue;
    }
    const double s = grid.spacing_m[d];
    const int cell = std::clamp(static_cast<int>(std::floor(u[d] / s)), 0, grid.counts[d] - 2);
    const double t = std::clamp(u[d] / s - cell, 0.0, 1.0);
    index[d] = {cell, cell + 1};
    value[d] = {1.0 - t, t};
    slope[d] = {-1.0 / s, 1.0 / s};
    terms[d] = 2;
  }
  out = {};
  for (int c = 0; c < terms[2]; ++c)
    for (int b = 0; b < terms[1]; ++b)
      for (int a = 0; a < terms[0]; ++a) {
        const double w = value[0][a] * value[1][b] * value[2][c];
        const std::array<double, 3> local{slope[0][a] * value[1][b] * value[2][c],
                                          value[0][a] * slope[1][b] * value[2][c],
                                          value[0][a] * value[1][b] * slope[2][c]};
        Point3 gradient{};
        for (int d = 0; d < 3; ++d) gradient = gradient + local[d] * grid.axes[d];
        out.frames.push_back(grid_frame_index(grid, index[0][a], index[1][b], index[2][c]));
        out.weights.push_back(w);
        out.gradients_per_m.push_back(gradient);
      }
}

Point3 world_of(const FrameGrid& grid, const Point3& u) {
  Point3 p = grid.origin_m;
  for (int d = 0; d < 3; ++d) p = p + u[d] * grid.axes[d];
  return p;
}

Status check_grid(const FrameGrid& grid) {
  int axes_with_frames = 0;
  for (int d = 0; d < 3; ++d) {
    const std::string axis = "[" + std::to_string(d) + "]";
    if (grid.counts[d] < 1) return field_error("every axis needs at least one frame", "counts" + axis);
    if (grid.counts[d] > 1) {
      ++axes_with_frames;
      if (!(grid.spacing_m[d] > 0.0 && std::isfinite(grid.spacing_m[d])))
        return field_error("the spacing must be positive", "spacing_m" + axis);
    } else if (!(grid.extent_m[d] > 0.0 && std::isfinite(grid.extent_m[d]))) {
      return field_error("an axis with one frame needs a positive extent (thickness or section)", "extent_m" + axis);
    }
    for (int e = 0; e < 3; ++e) {
      const double expected = d == e ? 1.0 : 0.0;
      if (!(std::abs(dot(grid.axes[d], grid.axes[e]) - expected) < 1e-9))
        return field_error("the axes must be orthonormal", "axes" + axis);
    }
  }
  if (axes_with_frames == 0) return field_error("a grid needs two frames along at least one axis", "counts");
  if (grid.points_per_cell_axis < 1 || grid.points_per_cell_axis > 4)
    return field_error("1 to 4 Gauss points per cell axis", "points_per_cell_axis");
  if (grid.points_across < 1 || grid.points_across > 4)
    return field_error("1 to 4 Gauss points across", "points_across");
  for (double c : grid.origin_m)
    if (!std::isfinite(c)) return field_error("the origin must be finite", "origin_m");
  return Done{};
}

/// Grid coordinates of a world point.
Point3 grid_coordinates(const FrameGrid& grid, const Point3& point_m) {
  const Point3 r = point_m - grid.origin_m;
  return {dot(r, grid.axes[0]), dot(r, grid.axes[1]), dot(r, grid.axes[2])};
}

}  // namespace

FrameTopology grid_topology(const FrameGrid& grid) {
  int axes_with_frames = 0;
  for (int count : grid.counts) axes_with_frames += count > 1 ? 1 : 0;
  return axes_with_frames == 3   ? FrameTopology::volume
         : axes_with_frames == 2 ? FrameTopology::surface
                                 : FrameTopology::line;
}

Result<FrameLayout> make_grid_layout(const FrameGrid& grid, const std::function<bool(const Point3&)>& keep) {
  if (auto s = check_grid(grid); !s) return s.error();
  // Per axis: the cells' starts and lengths, and the Gauss rule to use in them.
  std::array<std::vector<double>, 3> starts, lengths, gx, gw;
  for (int d = 0; d < 3; ++d) {
    if (grid.counts[d] == 1) {
      starts[d] = {-0.5 * grid.extent_m[d]};
      lengths[d] = {grid.extent_m[d]};
      gauss_rule(grid.points_across, gx[d], gw[d]);
    } else {
      for (int c = 0; c + 1 < grid.counts[d]; ++c) {
        starts[d].push_back(c * grid.spacing_m[d]);
        lengths[d].push_back(grid.spacing_m[d]);
      }
      gauss_rule(grid.points_per_cell_axis, gx[d], gw[d]);
    }
  }
  FrameLayout full;
  for (int k = 0; k < grid.counts[2]; ++k)
    for (int j = 0; j < grid.counts[1]; ++j)
      for (int i = 0; i < grid.counts[0]; ++i)
        full.frames_m.push_back(world_of(grid, {i * grid.spacing_m[0], j * grid.spacing_m[1], k * grid.spacing_m[2]}));
  full.neighbour_offsets.push_back(0);
  PointNeighbours neighbours;
  for (std::size_t c2 = 0; c2 < starts[2].size(); ++c2)
    for (std::size_t c1 = 0; c1 < starts[1].size(); ++c1)
      for (std::size_t c0 = 0; c0 < starts[0].size(); ++c0)
        for (std::size_t q2 = 0; q2 < gx[2].size(); ++q2)
          for (std::size_t q1 = 0; q1 < gx[1].size(); ++q1)
            for (std::size_t q0 = 0; q0 < gx[0].size(); ++q0) {
              const Point3 u{starts[0][c0] + gx[0][q0] * lengths[0][c0], starts[1][c1] + gx[1][q1] * lengths[1][c1],
                             starts[2][c2] + gx[2][q2] * lengths[2][c2]};
              const Point3 p = world_of(grid, u);
              if (keep && !keep(p)) continue;
              full.points_m.push_back(p);
              full.volumes_m3.push_back(gw[0][q0] * lengths[0][c0] * gw[1][q1] * lengths[1][c1] * gw[2][q2] *
                                        lengths[2][c2]);
              shape_functions(grid, u, neighbours);
              full.neighbour_frames.insert(full.neighbour_frames.end(), neighbours.frames.begin(),
                                           neighbours.frames.end());
              full.weights.insert(full.weights.end(), neighbours.weights.begin(), neighbours.weights.end());
              full.weight_gradients_per_m.insert(full.weight_gradients_per_m.end(), neighbours.gradients_per_m.begin(),
                                                 neighbours.gradients_per_m.end());
              full.neighbour_offsets.push_back(static_cast<std::int32_t>(full.neighbour_frames.size()));
            }
  if (full.points_m.empty()) return field_error("no integration point is kept", "keep");
  // Keep the frames that some point reaches, in grid order.
  std::vector<std::int32_t> renumber(full.frames_m.size(), -1);
  for (std::int32_t f : full.neighbour_frames) renumber[static_cast<std::size_t>(f)] = 0;
  FrameLayout layout = std::move(full);
  std::vector<Point3> all_frames = std::move(layout.frames_m);
  layout.frames_m.clear();
  for (std::size_t f = 0; f < all_frames.size(); ++f) {
    if (renumber[f] < 0) continue;
    renumber[f] = static_cast<std::int32_t>(layout.frames_m.size());
    layout.frames_m.push_back(all_frames[f]);
    layout.grid_frames.push_back(static_cast<std::int32_t>(f));
  }
  for (std::int32_t& f : layout.neighbour_frames) f = renumber[static_cast<std::size_t>(f)];
  return layout;
}

Result<PointNeighbours> grid_point_neighbours(const FrameGrid& grid, const FrameLayout& layout, const Point3& point_m) {
  if (auto s = check_grid(grid); !s) return s.error();
  PointNeighbours neighbours;
  shape_functions(grid, grid_coordinates(grid, point_m), neighbours);
  for (std::int32_t& f : neighbours.frames) {
    const auto it = std::lower_bound(layout.grid_frames.begin(), layout.grid_frames.end(), f);
    if (it == layout.grid_frames.end() || *it != f)
      return field_error("the point needs grid frame " + std::to_string(f) + ", which the layout does not have",
                         "point_m");
    f = static_cast<std::int32_t>(it - layout.grid_frames.begin());
  }
  return neighbours;
}

FrameLayout join_layouts(const std::vector<FrameLayout>& layouts) {
  FrameLayout joined;
  joined.neighbour_offsets.push_back(0);
  for (const FrameLayout& layout : layouts) {
    const auto frame_shift = static_cast<std::int32_t>(joined.frames_m.size());
    const auto pair_shift = static_cast<std::int32_t>(joined.neighbour_frames.size());
    joined.frames_m.insert(joined.frames_m.end(), layout.frames_m.begin(), layout.frames_m.end());
    joined.points_m.insert(joined.points_m.end(), layout.points_m.begin(), layout.points_m.end());
    joined.volumes_m3.insert(joined.volumes_m3.end(), layout.volumes_m3.begin(), layout.volumes_m3.end());
    for (std::size_t s = 1; s < layout.neighbour_offsets.size(); ++s)
      joined.neighbour_offsets.push_back(layout.neighbour_offsets[s] + pair_shift);
    for (std::int32_t f : layout.neighbour_frames) joined.neighbour_frames.push_back(f + frame_shift);
    joined.weights.insert(joined.weights.end(), layout.weights.begin(), layout.weights.end());
    joined.weight_gradients_per_m.insert(joined.weight_gradients_per_m.end(), layout.weight_gradients_per_m.begin(),
                                         layout.weight_gradients_per_m.end());
  }
  return joined;
}

}  // namespace nav
