#pragma once
// The lane kernels of the needle-tissue solver, compiled once per instruction set from
// needle_lane_kernels.isa.cpp (nav/core/kernel_isa.hpp): projected Gauss-Seidel on raw views
// of W and of the rows' laws, whose gap updates run as wide as the variant allows. Plain data
// only: the kernel source includes this header and nothing with inline functions. Internal
// to rtlib/nav/needle.
#include <cstddef>
#include <cstdint>

#include "nav/needle/row_law.hpp"

namespace nav::detail {

/// One row as the sweeps see it: its law and bounds, without its geometry.
struct SweepRow {
  double cap = 0.0;                   ///< as ConstraintRow::cap, newtons
  double friction_coefficient = 0.0;  ///< as ConstraintRow::friction_coefficient
  std::int32_t linked[2] = {-1, -1};  ///< as ConstraintRow::linked
  RowLaw law = RowLaw::bilateral;
  std::uint8_t point_rows = 0;  ///< on a constraint point's first row its row count (1 to kMaxRowsPerPoint), else 0
};

/// A projected Gauss-Seidel problem delta = delta_free + W lambda, as raw views.
struct SweepProblem {
  std::size_t m = 0;                ///< rows
  const SweepRow* rows = nullptr;   ///< m rows, constraint points consecutive
  const double* w = nullptr;        ///< m x m, column-major
  double* forces = nullptr;         ///< m: the warm start on entry, the solution on exit
  double* gaps = nullptr;           ///< m: the free gaps on entry, delta_free + W lambda on exit
};

/// The entry points of one instruction set's variant; every variant computes the same bits.
struct NeedleLaneKernels {
  /// Adds W forces to the gaps (the columns in order, zero forces skipped), then runs
  /// `sweeps` sweeps over the constraint points in order: each point's rows in turn with
  /// their gaps kept up to date within the point, the other rows' gaps once per point.
  void (*gauss_seidel)(const SweepProblem& problem, int sweeps) noexcept;
};

extern const NeedleLaneKernels needle_lane_kernels_baseline;
extern const NeedleLaneKernels needle_lane_kernels_avx2;    ///< x86-64 builds only
extern const NeedleLaneKernels needle_lane_kernels_avx512;  ///< x86-64 builds only

}  // namespace nav::detail
