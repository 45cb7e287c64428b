#pragma once
// Step-time reduced internal forces (and tangents) of a ReducedModel: the linear projection
// U^T K U, and the sampled, weighted corotational or St Venant-Kirchhoff tetrahedra of a
// cubature. noexcept, allocation-free, samples visited in order. Internal to
// rtlib/nav/reduced; also what the ECSW training evaluates element by element.
#include <span>

#include "nav/reduced/reduced_model.hpp"
#include "nav/reduced/reduced_tables.hpp"

namespace nav::detail {

/// The state a reduced force is evaluated at: coordinates q and diaphragm displacement d.
struct ReducedState {
  std::span<const double> q;
  const double* prescribed_m;  ///< 3 values
};

/// Displacements (12) of sample s's vertices and its deformation gradient (column-major 3x3).
void sample_deformation(const ReducedTables& t, int s, const ReducedState& state, double* u12, double* f9) noexcept;

/// force = -U^T K (U q + L d), the exact linear reduced force.
void linear_force(const ReducedTables& t, const ReducedState& state, std::span<double> force) noexcept;

// The cubature kinds approximate the non-linear remainder f(u) + K u of the elastic force
// only: their reduced force is -K_r q - K_rl d plus the weighted samples' remainders, so that
// a direction no sample sees keeps its linear stiffness.

/// force += sample s's reduced corotational remainder U_s^T w (f_s + K_s u_s), with rotation
/// R (column-major 3x3) and vertex displacements u12.
void add_corotational_force(const ReducedTables& t, int s, const double* u12, const double* rotation, std::span<double> force) noexcept;

/// The 6 x r rows V = sqrt(w V) D^1/2 B R^T U_s of sample s, whose V^T V is its reduced tangent.
void corotational_tangent_rows(const ReducedTables& t, int s, const double* rotation, std::span<double> rows) noexcept;

/// force += sample s's reduced St Venant-Kirchhoff remainder at displacements u12 and
/// deformation gradient f9.
void add_stvk_force(const ReducedTables& t, int s, const double* u12, const double* f9, std::span<double> force) noexcept;

/// tangent += sample s's reduced St Venant-Kirchhoff tangent (r x r, positive semi-definite).
void add_stvk_tangent(const ReducedTables& t, int s, const double* f9, std::span<double> tangent) noexcept;

/// Scratch of evaluate_internal_force, carved from a ReducedData.
struct ForceScratch {
  std::span<double> displacements;  ///< 12 per sample
  std::span<double> rotations;      ///< 9 per sample: the last good rotation, kept between calls
  std::span<double> tangent_rows;   ///< 6 r: one sample's tangent rows
  std::span<double> monomials;      ///< the cubic polynomial's monomials
};

/// force = reduced elastic force at `state` (springs excluded); when `tangent` is not empty it
/// gets the reduced elastic tangent (K_r - sum w U_s^T K_s U_s + the samples' tangents). Returns how many samples had det F <= 0 (they keep
/// their previous rotation).
int evaluate_internal_force(const ReducedTables& t, const ReducedState& state, ForceScratch scratch, std::span<double> force,
                            std::span<double> tangent) noexcept;

}  // namespace nav::detail
