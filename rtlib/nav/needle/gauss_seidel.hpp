#pragma once
// Projected Gauss-Seidel on delta = delta_free + W lambda with the row laws of
// ConstraintRow: a fixed number of sweeps in a fixed order (the rows of one constraint point
// in turn, their effect on the others applied once per point; of P points, the first half
// interleaved with the second: 0, H, 1, H + 1, ... with H = ceil(P / 2)), warm-started from
// the given forces, then the largest law violation as the residual. The sweeps run in the lane
// kernels of an instruction set (needle_lane_kernels.hpp), every variant the same bits. No
// allocation.
#include <span>

#include "nav/core/kernel_isa.hpp"
#include "nav/needle/constraint_row.hpp"
#include "nav/needle/needle_lane_kernels.hpp"

namespace nav {

/// Relative slack under which a force counts as at its bound (a friction or puncture limit).
inline constexpr double kForceAtBoundSlack = 1e-9;

/// Where the solver works: one sweep row per constraint row, and the kernels' variant.
struct GaussSeidelWorkspace {
  std::span<detail::SweepRow> rows;
  const detail::NeedleLaneKernels* kernels = &detail::needle_lane_kernels_baseline;
};

/// Runs `sweeps` sweeps. `w` is m x m column-major, its columns `w_stride` (>= m) apart,
/// `forces` (m) holds the warm start on entry and the solution on exit, `gaps` (m) receives
/// delta_free + W lambda; `work.rows` holds at least m rows. Returns the largest violation of
/// the laws, in metres.
double solve_gauss_seidel(std::span<const ConstraintRow> rows, std::span<const double> w, std::size_t w_stride,
                          int sweeps, std::span<double> forces, std::span<double> gaps,
                          const GaussSeidelWorkspace& work) noexcept;

/// The violation of one row's law by (gap, force), in metres (0 when it holds).
double law_violation_m(const ConstraintRow& row, double gap_m, double force_n, double limit_n) noexcept;

/// The violation of Coulomb's disk by a tangent pair: stick inside the disk, slip opposite
/// to the force on its rim, in metres.
double coulomb_disk_violation_m(std::span<const double> gaps, std::span<const double> forces, double limit_n) noexcept;

/// The force bound of a friction or Coulomb row given the current forces.
double row_limit_n(std::span<const ConstraintRow> rows, std::size_t row, std::span<const double> forces) noexcept;

namespace detail {

/// The solver's lane kernels of `isa` (`best` resolved); baseline when it is not available.
const NeedleLaneKernels& needle_lane_kernels(KernelIsa isa) noexcept;

}  // namespace detail

}  // namespace nav
