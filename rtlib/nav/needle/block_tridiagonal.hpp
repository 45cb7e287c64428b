#pragma once
// The O(n) solver of the needle: a symmetric positive definite block-tridiagonal matrix with
// 6x6 blocks (one per free node) factored as L D L^T with D the Schur complements (kept as
// their inverses, from a fixed-size Cholesky), solved by one forward and one backward sweep
// of 6x6 products, and the translational blocks of
// its inverse (Duriez's compliance, Eq. 1.15) by the Takahashi recurrence. Storage is
// preallocated by the caller; nothing here allocates.
#include <span>

namespace nav {

/// Views of the matrix and factor storage, 36 doubles (column-major 6x6) per block row.
struct BlockTridiagonal {
  int blocks = 0;
  std::span<double> diagonal;    ///< A_kk
  std::span<double> upper;       ///< A_k,k+1 (the last one unused)
  std::span<double> schur;       ///< S_k^-1, S_k = A_kk - L_k A_k-1,k (symmetric)
  std::span<double> multiplier;  ///< L_k = A_k-1,k^T S_k-1^-1 (the first one unused)
};

/// Factors in place. False when a Schur complement is not positive definite.
bool factor_block_tridiagonal(BlockTridiagonal& matrix) noexcept;

/// Overwrites rhs (6 per block row) with A^-1 rhs, using the factor.
void solve_block_tridiagonal(const BlockTridiagonal& matrix, std::span<double> rhs) noexcept;

/// The 3x3 translational blocks C_ij = (A^-1)_ij[0:3, 0:3] for first_block <= i, j < blocks,
/// written into the dense row-major `out` (`out_stride` values per row, at least 3 per
/// block): C_ij(a, b) at out[(3 i + a) * out_stride + 3 j + b], exactly symmetric.
/// `diagonal_work` holds 36 per block and `column_work` 18 per block.
void translational_inverse_blocks(const BlockTridiagonal& matrix, int first_block, std::span<double> diagonal_work,
                                  std::span<double> column_work, std::span<double> out,
                                  std::size_t out_stride) noexcept;

}  // namespace nav
