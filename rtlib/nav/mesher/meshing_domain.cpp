#include "nav/mesher/meshing_domain.hpp"

namespace nav {

void MeshingDomain::classify_column(double x_m, double y_m, double z0_m, double dz_m,
                                    std::span<std::uint8_t> inside) const {
  for (std::size_t k = 0; k < inside.size(); ++k) {
    inside[k] = contains({x_m, y_m, z0_m + static_cast<double>(k) * dz_m}) ? 1 : 0;
  }
}

}  // namespace nav
