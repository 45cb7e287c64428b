#pragma once
// Where the frames and integration points of a meshless frame-based tissue (Bosman et al.,
// digest 002) sit, and the shape functions that tie every point to its frames: a regular
// grid of frames with tensor-product Lagrange shape functions (trilinear with 8 neighbours
// for a volume, bilinear with 4 for a surface, linear with 2 for a line; the paper's choice),
// sampled by Gauss points per cell. Init-time code; plain data, no Eigen.
#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include "nav/core/error.hpp"
#include "nav/mesh/tet_mesh.hpp"

namespace nav {

/// The frames and integration points of one tissue and the shape functions between them.
/// Point s has neighbours [neighbour_offsets[s], neighbour_offsets[s+1]); for each, the frame,
/// its weight w_is and the rest gradient of w_i at the point. Weights sum to one and their
/// gradients to zero (partition of unity), so that the rest deformation gradient is I.
struct FrameLayout {
  std::vector<Point3> frames_m;    ///< frame rest positions (rest orientations: identity)
  std::vector<Point3> points_m;    ///< integration point rest positions
  std::vector<double> volumes_m3;  ///< volume each point integrates
  std::vector<std::int32_t> neighbour_offsets;
  std::vector<std::int32_t> neighbour_frames;
  std::vector<double> weights;
  std::vector<Point3> weight_gradients_per_m;
  /// For a grid layout, the grid index (grid_frame_index) of each frame; else empty.
  std::vector<std::int32_t> grid_frames;
};

/// What a grid of frames models, from how many of its axes have more than one frame.
enum class FrameTopology {
  volume,   ///< frames along three axes: a block (ligament)
  surface,  ///< frames along two axes, a thickness across the third: a membrane
  line,     ///< frames along one axis, a cross-section across the other two: a cord
};

/// A regular grid of frames: frame (i, j, k) rests at origin + i s0 a0 + j s1 a1 + k s2 a2
/// for orthonormal axes a. An axis with one frame has no shape function along it: its
/// extent_m (thickness of a surface, side of a line's square section) is sampled by Gauss
/// points that all follow the frames' rotations.
struct FrameGrid {
  Point3 origin_m{};
  std::array<Point3, 3> axes{{{1.0, 0.0, 0.0}, {0.0, 1.0, 0.0}, {0.0, 0.0, 1.0}}};
  std::array<int, 3> counts{2, 2, 2};
  std::array<double, 3> spacing_m{0.01, 0.01, 0.01};
  /// Extent across each axis that has one frame, centred on the frames.
  std::array<double, 3> extent_m{0.0, 0.0, 0.0};
  /// Gauss points per cell along each axis with several frames (1 to 4).
  int points_per_cell_axis = 2;
  /// Gauss points across each axis with one frame (1: coplanar or collinear points).
  int points_across = 2;
};

/// The topology of a grid (volume, surface or line).
FrameTopology grid_topology(const FrameGrid& grid);

/// Index of frame (i, j, k) in the grid's frame order (i fastest).
inline std::int32_t grid_frame_index(const FrameGrid& grid, int i, int j, int k) {
  return static_cast<std::int32_t>(i + grid.counts[0] * (j + grid.counts[1] * k));
}

/// The layout of `grid`: every frame, and Gauss points in every cell, keeping only those
/// for which `keep` (when given) is true (a cylinder in a box grid); frames that no kept
/// point reaches are removed. Errors name the field at fault.
Result<FrameLayout> make_grid_layout(const FrameGrid& grid, const std::function<bool(const Point3&)>& keep = {});

/// The frames of a layout that carry a material point, with their weights and weight
/// gradients: the shape functions at a point that is not an integration point (a probe).
struct PointNeighbours {
  std::vector<std::int32_t> frames;
  std::vector<double> weights;
  std::vector<Point3> gradients_per_m;
};

/// Neighbours of rest point `point_m` in `layout`, made by make_grid_layout(grid) (the point
/// is clamped into the grid along axes with several frames). An Error if one of them was
/// removed from the layout.
Result<PointNeighbours> grid_point_neighbours(const FrameGrid& grid, const FrameLayout& layout, const Point3& point_m);

/// Joins layouts of several tissues into one (frame indices of the later ones shifted, grid
/// indices dropped), so that one model solves them together.
FrameLayout join_layouts(const std::vector<FrameLayout>& layouts);

}  // namespace nav
