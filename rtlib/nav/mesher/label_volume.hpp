#pragma once
// A 3-D label image such as a CT segmentation: one byte per voxel on a regular grid.
#include <array>
#include <cstdint>
#include <vector>

#include "nav/mesh/tet_mesh.hpp"

namespace nav {

/// Voxel labels on a regular, axis-aligned grid, x fastest then y then z. Voxel (i, j, k) has
/// its centre at origin_m + (i spacing_m[0], j spacing_m[1], k spacing_m[2]); label 0 is
/// background, any other value is tissue.
struct LabelVolume {
  std::array<std::int32_t, 3> size{};  ///< voxels along x, y, z
  Point3 spacing_m{};
  Point3 origin_m{};                 ///< centre of voxel (0, 0, 0)
  std::vector<std::uint8_t> labels;  ///< size[0] * size[1] * size[2] values

  /// The label of voxel (i, j, k), 0 outside the grid.
  std::uint8_t at(std::int64_t i, std::int64_t j, std::int64_t k) const {
    if (i < 0 || j < 0 || k < 0 || i >= size[0] || j >= size[1] || k >= size[2]) return 0;
    return labels[static_cast<std::size_t>(i + size[0] * (j + static_cast<std::int64_t>(size[1]) * k))];
  }
};

}  // namespace nav
