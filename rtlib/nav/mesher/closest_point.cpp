#include "nav/mesher/closest_point.hpp"

#include <algorithm>

namespace nav {

Point3 closest_point_on_segment(const Point3& p, const Point3& a, const Point3& b) {
  const Point3 ab = b - a;
  const double length_squared = dot(ab, ab);
  if (length_squared <= 0.0) return a;
  const double t = std::clamp(dot(p - a, ab) / length_squared, 0.0, 1.0);
  return a + t * ab;
}

Point3 closest_point_on_triangle(const Point3& p, const Point3& a, const Point3& b, const Point3& c) {
  const Point3 normal = cross(b - a, c - a);
  const double normal_squared = dot(normal, normal);
  if (normal_squared > 0.0) {
    // The projection onto the plane is the answer when it falls inside the triangle.
    const Point3 q = p - (dot(p - a, normal) / normal_squared) * normal;
    const bool inside = dot(normal, cross(b - a, q - a)) >= 0.0 && dot(normal, cross(c - b, q - b)) >= 0.0 &&
                        dot(normal, cross(a - c, q - c)) >= 0.0;
    if (inside) return q;
  }
  // Otherwise the closest point lies on an edge.
  const Point3 candidates[3] = {closest_point_on_segment(p, a, b), closest_point_on_segment(p, b, c),
                                closest_point_on_segment(p, c, a)};
  Point3 best = candidates[0];
  double best_squared = dot(p - best, p - best);
  for (int e = 1; e < 3; ++e) {
    const double d2 = dot(p - candidates[e], p - candidates[e]);
    if (d2 < best_squared) {
      best_squared = d2;
      best = candidates[e];
    }
  }
  return best;
}

}  // namespace nav
