#include "nav/mesher/crease.hpp"

namespace nav {

bool bends_into_crease(const std::vector<Point3>& face_normals, double crease_cosine) {
  std::vector<Point3> unit;
  for (const Point3& n : face_normals) {
    const double length = norm(n);
    if (length > 0.0) unit.push_back((1.0 / length) * n);
  }
  for (std::size_t i = 0; i < unit.size(); ++i)
    for (std::size_t j = i + 1; j < unit.size(); ++j)
      if (dot(unit[i], unit[j]) < crease_cosine) return true;
  return false;
}

}  // namespace nav
