#include "nav/needle/needle_parameters.hpp"

#include <cmath>
#include <numbers>
#include <string>

namespace nav {

namespace {

Status field_error(const char* field, const std::string& message) {
  return Error{.message = message, .field = std::string("needle.") + field};
}

bool in_range(double value, double low, double high) { return std::isfinite(value) && value >= low && value <= high; }

}  // namespace

Status validate_needle_parameters(const NeedleParameters& p) {
  if (!in_range(p.length_m, 1e-3, 1.0)) return field_error("length_m", "must be within [1 mm, 1 m]");
  if (!in_range(p.outer_diameter_m, 1e-5, 0.01))
    return field_error("outer_diameter_m", "must be within [10 um, 10 mm]");
  if (!in_range(p.inner_diameter_m, 0.0, p.outer_diameter_m) || !(p.inner_diameter_m < p.outer_diameter_m))
    return field_error("inner_diameter_m", "must be within [0, outer_diameter_m)");
  if (!in_range(p.youngs_modulus_pa, 1e6, 1e12))
    return field_error("youngs_modulus_pa", "must be within [1 MPa, 1 TPa]");
  if (!in_range(p.poisson_ratio, 0.0, 0.49)) return field_error("poisson_ratio", "must be within [0, 0.49]");
  if (!in_range(p.density_kg_m3, 100.0, 30000.0)) return field_error("density_kg_m3", "must be within [100, 30000]");
  if (!in_range(p.bevel_angle_rad, 0.05, std::numbers::pi / 2))
    return field_error("bevel_angle_rad", "must be within [0.05, pi/2] (pi/2 is a blunt, symmetric tip)");
  if (p.element_count < 1 || p.element_count > 256) return field_error("element_count", "must be within [1, 256]");
  if (!in_range(p.step_s, 1e-6, 1.0)) return field_error("step_s", "must be within [1 us, 1 s]");
  if (p.newton_iterations < 1 || p.newton_iterations > 100)
    return field_error("newton_iterations", "must be within [1, 100]");
  if (!in_range(p.rayleigh_mass_per_s, 0.0, 1e6)) return field_error("rayleigh_mass_per_s", "must be within [0, 1e6]");
  if (!in_range(p.max_pose_jump_m, 0.0, 1.0) || p.max_pose_jump_m == 0.0)
    return field_error("max_pose_jump_m", "must be within (0, 1 m]");
  return Done{};
}

NeedleSection needle_section(const NeedleParameters& p) {
  const double ro = 0.5 * p.outer_diameter_m, ri = 0.5 * p.inner_diameter_m;
  const double m = ri / ro, m2 = m * m, nu = p.poisson_ratio;
  NeedleSection s;
  s.area_m2 = std::numbers::pi * (ro * ro - ri * ri);
  s.second_moment_m4 = 0.25 * std::numbers::pi * (ro * ro * ro * ro - ri * ri * ri * ri);
  s.polar_moment_m4 = 2.0 * s.second_moment_m4;
  // Cowper (1966), hollow circular section.
  s.shear_coefficient = 6.0 * (1.0 + nu) * (1.0 + m2) * (1.0 + m2) /
                        ((7.0 + 6.0 * nu) * (1.0 + m2) * (1.0 + m2) + (20.0 + 12.0 * nu) * m2);
  s.shear_modulus_pa = p.youngs_modulus_pa / (2.0 * (1.0 + nu));
  return s;
}

}  // namespace nav
