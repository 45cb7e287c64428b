#pragma once
// Step-time reduced internal forces (and tangents) of a ReducedModel: the linear projection
// U^T K U, and the sampled, weighted corotational or St Venant-Kirchhoff tetrahedra of a
// cubature through the blocked kernels of reduced_kernels.hpp. noexcept, allocation-free,
// bitwise repeatable. Internal to rtlib/nav/reduced.
#include <cstddef>
#include <span>

#include "nav/reduced/reduced_kernels.hpp"
#include "nav/reduced/reduced_model.hpp"
#include "nav/reduced/reduced_tables.hpp"

namespace nav::detail {

/// force = -U^T K (U q + L d), the exact linear reduced force.
void linear_force(const ReducedTables& t, const ReducedState& state, std::span<double> force) noexcept;

// The cubature kinds approximate the non-linear remainder f(u) + K u of the elastic force
// only: their reduced force is -K_r q - K_rl d plus the weighted samples' remainders, so that
// a direction no sample sees keeps its linear stiffness. It is evaluated as
// -(K_r - K_S) q - (K_rl - K_Sl) d plus the samples' whole forces.

/// Scratch of evaluate_internal_force, carved from a ReducedData (see force_scratch_sizes).
struct ForceScratch {
  std::span<double> displacements;  ///< 12 per (padded) sample, blocked
  std::span<double> rotations;      ///< 9 per (padded) sample, blocked: the last good rotations, kept between calls
  std::span<double> tangent_rows;   ///< the lanes' forces (r kSampleLanes), then the tangent rows of a block
  std::span<double> monomials;      ///< the cubic polynomial's monomials
};

/// The sizes (doubles) of the ForceScratch spans other than the monomials.
struct ForceScratchSizes {
  std::size_t displacements = 0, rotations = 0, tangent_rows = 0;
};
ForceScratchSizes force_scratch_sizes(const ReducedTables& t) noexcept;

/// force = reduced elastic force at `state` (springs excluded); when `tangent` is not empty it
/// gets the reduced elastic tangent (K_r - K_S + the samples' tangents). Returns how many
/// samples had det F <= 0 (they keep their previous rotation).
int evaluate_internal_force(const ReducedTables& t, const ReducedState& state, ForceScratch scratch,
                            std::span<double> force, std::span<double> tangent) noexcept;

}  // namespace nav::detail
