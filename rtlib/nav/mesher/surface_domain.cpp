#include "nav/mesher/surface_domain.hpp"

#include <vector>

namespace nav {

SurfaceDomain::SurfaceDomain(const TriSurface& surface)
    : bounds_(bounds_of(surface.vertices_m)), rays_(surface), proximity_(surface) {}

bool SurfaceDomain::contains(const Point3& point_m) const {
  std::uint8_t inside = 0;
  classify_column(point_m[0], point_m[1], point_m[2], 0.0, {&inside, 1});
  return inside != 0;
}

void SurfaceDomain::classify_column(double x_m, double y_m, double z0_m, double dz_m,
                                    std::span<std::uint8_t> inside) const {
  std::vector<double> crossings_z_m;
  rays_.crossings_z(x_m, y_m, crossings_z_m);
  // A point is inside when an odd number of crossings lies above it.
  std::size_t below = 0;
  for (std::size_t k = 0; k < inside.size(); ++k) {
    const double z_m = z0_m + static_cast<double>(k) * dz_m;
    while (below < crossings_z_m.size() && crossings_z_m[below] <= z_m) ++below;
    inside[k] = ((crossings_z_m.size() - below) % 2 == 1) ? 1 : 0;
  }
}

}  // namespace nav
