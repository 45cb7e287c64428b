#pragma once
// Exact Euclidean distance maps on regular grids (Felzenszwalb and Huttenlocher's separable
// lower-envelope algorithm), used to give label volumes a gradient far from their boundary.
#include <array>
#include <cstdint>
#include <vector>

#include "nav/mesh/geometry.hpp"

namespace nav {

/// For a grid of `size` samples (x fastest) with spacing `spacing_m`, the distance in metres
/// from every sample to the nearest sample of the other class, negative for samples in the
/// class `inside` (inside[i] != 0), positive for the others. A grid with one class only gets
/// +-1e10 m.
std::vector<float> signed_distance_map_m(const std::vector<std::uint8_t>& inside,
                                         const std::array<std::int64_t, 3>& size, const Point3& spacing_m);

}  // namespace nav
