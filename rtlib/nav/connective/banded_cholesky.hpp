#pragma once
// In-place Cholesky factorisation and solve of a symmetric positive definite band matrix
// stored by lower columns: entry (i, j), j <= i <= j + b, at j (b + 1) + (i - j). Fixed cost
// n b^2 / 2, no allocation, a fixed order of operations.
#include <cstddef>
#include <span>

namespace nav {

/// Replaces the band by its Cholesky factor L (A = L L^T); false (band left partly
/// overwritten) when a pivot is not positive or not finite.
bool banded_cholesky_factor(std::span<double> band, std::size_t n, std::size_t half_bandwidth) noexcept;

/// Solves L L^T x = x in place with the factor of banded_cholesky_factor.
void banded_cholesky_solve(std::span<const double> factor, std::size_t n, std::size_t half_bandwidth,
                           std::span<double> x) noexcept;

}  // namespace nav
