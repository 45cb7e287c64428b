#pragma once
// What a flexible needle is made of and how it is stepped: geometry, material, beam theory,
// discretisation and the limits of its tracked base pose. Validated once at init; every
// error names the field at fault.
#include <cstdint>

#include "nav/core/error.hpp"

namespace nav {

/// The beam theory of the needle's elements.
enum class BeamTheory {
  euler_bernoulli,  ///< no shear deformation
  timoshenko,       ///< shear deformation with Cowper's shear coefficient of a tube
};

/// How a needle step integrates in time.
enum class NeedleIntegrator {
  implicit_euler,  ///< backward Euler, lumped mass and rotary inertia, Rayleigh mass damping
  quasi_static,    ///< equilibrium only (mass and velocity ignored)
};

/// Geometry, material and numerical settings of a straight hollow needle. The needle lies
/// along +x of its base frame (the tracked pose), from the base (node 0) to the tip.
struct NeedleParameters {
  double length_m = 0.15;
  double outer_diameter_m = 1.27e-3;  ///< 18 gauge
  double inner_diameter_m = 0.84e-3;  ///< 0 for a solid stylet
  double youngs_modulus_pa = 200e9;   ///< stainless steel
  double poisson_ratio = 0.3;
  double density_kg_m3 = 7850.0;
  double bevel_angle_rad = 0.5236;  ///< angle between the bevel face and the shaft (30 deg)
  BeamTheory theory = BeamTheory::timoshenko;
  int element_count = 20;
  NeedleIntegrator integrator = NeedleIntegrator::implicit_euler;
  double step_s = 1e-3;
  int newton_iterations = 1;  ///< fixed count per step
  double rayleigh_mass_per_s = 0.0;
  /// A base pose that moves farther than this in one step is rejected as a tracking glitch.
  double max_pose_jump_m = 0.01;
};

/// Cross-section constants of the tube, in SI units.
struct NeedleSection {
  double area_m2 = 0.0;
  double second_moment_m4 = 0.0;   ///< I about either bending axis
  double polar_moment_m4 = 0.0;    ///< J = 2 I
  double shear_coefficient = 0.0;  ///< Cowper's kappa for a hollow circle
  double shear_modulus_pa = 0.0;
};

/// Checks every field (finite, in range, consistent); the Error's field names the culprit.
Status validate_needle_parameters(const NeedleParameters& parameters);

/// The section constants of valid parameters.
NeedleSection needle_section(const NeedleParameters& parameters);

}  // namespace nav
