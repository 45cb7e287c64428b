#pragma once
// Init-time selection of boundary-condition regions on a mesh.
#include <cstdint>
#include <string>
#include <vector>

#include "nav/core/error.hpp"
#include "nav/mesh/geometry.hpp"

namespace nav {

/// The nodes of `mesh` inside the closed box `box_m`, ascending. A box that selects no node
/// is an Error whose field is `field`.
Result<std::vector<std::int32_t>> nodes_in_box(const TetMesh& mesh, const Bounds3& box_m, const std::string& field);

}  // namespace nav
