#pragma once
// Isotropic linear elastic material parameters shared by every tissue model, their Lamé
// form, and the init-time check that says which parameter is out of range.
#include <string>

#include "nav/core/error.hpp"

namespace nav {

/// An isotropic linear elastic material. Default-constructed, it is kLiverParenchyma.
struct ElasticMaterial {
  double youngs_modulus_pa = 5000.0;
  double poisson_ratio = 0.45;
  double density_kg_m3 = 1060.0;
};

/// Liver parenchyma (E 5 kPa, nu 0.45, 1060 kg/m^3): what a TissueScene or a station scene
/// that states no material gets. State it to get another.
inline constexpr ElasticMaterial kLiverParenchyma{};

/// Lamé's first parameter and the shear modulus of an ElasticMaterial.
struct LameParameters {
  double lambda_pa = 0.0;
  double mu_pa = 0.0;
};

/// lambda = E nu / ((1 + nu)(1 - 2 nu)), mu = E / (2 (1 + nu)).
LameParameters lame_parameters(const ElasticMaterial& material);

/// Init-time check: E > 0, -1 < nu < 0.5, density > 0, all finite. The Error's field is
/// `field` + ".youngs_modulus_pa" (or the parameter at fault).
Status check_material(const ElasticMaterial& material, const std::string& field);

}  // namespace nav
