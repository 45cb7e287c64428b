#pragma once
// Closest points on segments and triangles: the kernel of surface projection.
#include "nav/mesh/geometry.hpp"

namespace nav {

/// The point of the segment [a, b] closest to `p` (a itself if the segment has no length).
Point3 closest_point_on_segment(const Point3& p, const Point3& a, const Point3& b);

/// The point of the triangle (a, b, c), interior included, closest to `p`. A degenerate
/// (zero-area) triangle is treated as its three edges.
Point3 closest_point_on_triangle(const Point3& p, const Point3& a, const Point3& b, const Point3& c);

}  // namespace nav
