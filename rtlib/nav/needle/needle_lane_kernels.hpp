#pragma once
// The lane kernels of the needle-tissue solver, compiled once per instruction set from
// needle_lane_kernels.isa.cpp (nav/core/kernel_isa.hpp): projected Gauss-Seidel on raw views
// of W and of the rows' laws, whose gap updates run as wide as the variant allows, and the
// sparse-times-dense row combinations that assemble the low-rank W with the transpositions
// between them, and the nearest tissue node of a point, which tissue points attach to. Plain data
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
  double inverse_diagonal = 0.0;      ///< 1 / W_rr, or 0 when W_rr is not positive (the row is skipped)
  std::int32_t linked[2] = {-1, -1};  ///< as ConstraintRow::linked
  /// On a point's first row: the first row of the point a sweep visits next, -1 after the last.
  std::int32_t next_point = -1;
  RowLaw law = RowLaw::bilateral;
  std::uint8_t point_rows = 0;  ///< on a constraint point's first row its row count (1 to kMaxRowsPerPoint), else 0
};

/// A projected Gauss-Seidel problem delta = delta_free + W lambda, as raw views.
struct SweepProblem {
  std::size_t m = 0;               ///< rows
  const SweepRow* rows = nullptr;  ///< m rows, constraint points consecutive
  const double* w = nullptr;       ///< m x m, column-major
  std::size_t w_stride = 0;        ///< between W's columns, at least m
  double* forces = nullptr;        ///< m: the warm start on entry, the solution on exit
  double* gaps = nullptr;          ///< m: the free gaps on entry, delta_free + W lambda on exit
};

/// The most entries per row of a RowCombination.
inline constexpr std::size_t kMaxCombinedTerms = 9;

/// Values a RowCombination's row lengths are rounded up to (the widest variant's lanes), so
/// that no variant finishes a row value by value: strides and buffers are padded to it.
inline constexpr std::size_t kCombinedLanes = 8;

/// The bytes of kCombinedLanes values: the buffers the kernels run along start on a multiple
/// of it, and with strides of whole lanes every row does, so that no load straddles two cache lines.
inline constexpr std::size_t kLaneBytes = kCombinedLanes * sizeof(double);

/// Sparse rows times a dense matrix, out_r = sum_k c_rk dense_(source_rk), the terms in
/// order: the compliance assembly's products H (C H^T) with H's few entries per row.
struct RowCombination {
  std::size_t rows = 0;
  std::size_t terms = 0;                  ///< entries per row, 1 to kMaxCombinedTerms
  std::size_t term_stride = 0;            ///< between the entries of consecutive rows
  const double* coefficients = nullptr;   ///< c_rk at [r * term_stride + k]
  const std::int32_t* sources = nullptr;  ///< rows of `dense`, as the coefficients
  const double* dense = nullptr;          ///< row i at dense + i * dense_stride
  std::size_t dense_stride = 0;
  std::size_t width = 0;  ///< values per output row, a multiple of kCombinedLanes
  /// Output row r stops at r + 1 values rounded up to kCombinedLanes (at most `width`): the
  /// values past r + 1 are the upper triangle's, for the caller to overwrite.
  bool lower_triangle = false;
  double* out = nullptr;  ///< row r at out + r * out_stride
  std::size_t out_stride = 0;
};

/// The tissue node nearest a point: node n at rest_m[3n..3n+3) plus, for n < displaced,
/// displacements_m[3n..3n+3); its squared distance summed x, y, then z.
struct NearestNodeQuery {
  const double* rest_m = nullptr;
  const double* displacements_m = nullptr;
  std::size_t nodes = 0;
  std::size_t displaced = 0;  ///< at most nodes
  double point_m[3] = {0.0, 0.0, 0.0};
};

/// A dense block copied transposed: dst[c * dst_stride + r] = src[r * src_stride + c] for
/// r < rows, c < cols (the blocks do not overlap).
struct Transposition {
  const double* src = nullptr;
  std::size_t src_stride = 0;
  std::size_t rows = 0;
  std::size_t cols = 0;
  double* dst = nullptr;
  std::size_t dst_stride = 0;
};

/// The entry points of one instruction set's variant; every variant computes the same bits.
struct NeedleLaneKernels {
  /// Adds W forces to the gaps (the columns in order, zero forces skipped), then runs
  /// `sweeps` sweeps over the constraint points from row 0 along next_point: each point's
  /// rows in turn with their gaps kept up to date within the point, the other rows' gaps
  /// once per point.
  void (*gauss_seidel)(const SweepProblem& problem, int sweeps) noexcept;
  /// Fills the output rows of a RowCombination, each value summed over k in order.
  void (*combine_rows)(const RowCombination& product) noexcept;
  /// The nearest node, as a scan in node order that keeps the first of equals would find it
  /// (node 0 whatever its distance, then each node strictly nearer than the best so far: a
  /// NaN distance never wins); -1 when there is no node.
  std::int32_t (*nearest_node)(const NearestNodeQuery& query) noexcept;
  /// Copies a Transposition, eight by eight values through registers.
  void (*transpose)(const Transposition& block) noexcept;
  /// Completes a symmetric n x n matrix (row i at a + i * stride) from its lower triangle:
  /// a[s * stride + r] = a[r * stride + s] for r > s.
  void (*mirror_lower)(double* a, std::size_t n, std::size_t stride) noexcept;
};

extern const NeedleLaneKernels needle_lane_kernels_baseline;
extern const NeedleLaneKernels needle_lane_kernels_avx2;    ///< x86-64 builds only
extern const NeedleLaneKernels needle_lane_kernels_avx512;  ///< x86-64 builds only

}  // namespace nav::detail
