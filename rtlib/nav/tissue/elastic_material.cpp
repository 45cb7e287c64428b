#include "nav/tissue/elastic_material.hpp"

#include <cmath>

namespace nav {

LameParameters lame_parameters(const ElasticMaterial& material) {
  const double e = material.youngs_modulus_pa;
  const double nu = material.poisson_ratio;
  return {e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)), e / (2.0 * (1.0 + nu))};
}

Status check_material(const ElasticMaterial& material, const std::string& field) {
  if (!(std::isfinite(material.youngs_modulus_pa) && material.youngs_modulus_pa > 0.0))
    return Error{.message = "Young's modulus must be a positive number of pascals",
                 .field = field + ".youngs_modulus_pa"};
  if (!(material.poisson_ratio > -1.0 && material.poisson_ratio < 0.5))
    return Error{.message = "Poisson's ratio must lie in (-1, 0.5)", .field = field + ".poisson_ratio"};
  if (!(std::isfinite(material.density_kg_m3) && material.density_kg_m3 > 0.0))
    return Error{.message = "the density must be a positive number of kg/m^3", .field = field + ".density_kg_m3"};
  return Done{};
}

}  // namespace nav
