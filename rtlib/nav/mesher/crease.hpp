#pragma once
// Creases of a triangulated boundary: where its faces bend sharply (edges and corners of boxes).
#include <vector>

#include "nav/mesh/geometry.hpp"

namespace nav {

/// True if two of the faces whose normals (any length; zero ones are ignored) are given bend
/// by more than the crease angle: the cosine between their directions is below `crease_cosine`.
bool bends_into_crease(const std::vector<Point3>& face_normals, double crease_cosine);

}  // namespace nav
