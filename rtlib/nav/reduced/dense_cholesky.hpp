#pragma once
// The dense kernels of the reduced step: dot products, r x r system assembly, Cholesky factorisation and
// solve, in plain loops (a fixed summation order on every architecture, no allocation).
// Internal to rtlib/nav/reduced. Matrices are row-major r x r.
#include <cmath>
#include <span>

namespace nav::detail {

/// The dot product of a and b (n values) summed in four interleaved partial sums, combined
/// as (s0 + s1) + (s2 + s3), then the tail: a fixed order on every architecture, and four
/// independent dependency chains instead of one.
inline double dot(const double* a, const double* b, int n) noexcept {
  double s0 = 0.0, s1 = 0.0, s2 = 0.0, s3 = 0.0;
  int j = 0;
  for (; j + 4 <= n; j += 4) {
    s0 += a[j] * b[j];
    s1 += a[j + 1] * b[j + 1];
    s2 += a[j + 2] * b[j + 2];
    s3 += a[j + 3] * b[j + 3];
  }
  double sum = (s0 + s1) + (s2 + s3);
  for (; j < n; ++j) sum += a[j] * b[j];
  return sum;
}

/// out = identity_coefficient I + stiffness_coefficient K + spring_coefficient Ks.
inline void system_matrix(std::span<const double> k, std::span<const double> ks, double identity_coefficient,
                          double stiffness_coefficient, double spring_coefficient, int r,
                          std::span<double> out) noexcept {
  for (int i = 0; i < r * r; ++i) out[i] = stiffness_coefficient * k[i] + spring_coefficient * ks[i];
  for (int i = 0; i < r; ++i) out[i * r + i] += identity_coefficient;
}

/// Overwrites the lower triangle of the symmetric `a` with its Cholesky factor L (A = L L^T).
/// False when a pivot is not positive (the matrix is then left partly overwritten).
inline bool cholesky_in_place(std::span<double> a, int r) noexcept {
  for (int j = 0; j < r; ++j) {
    double pivot = a[j * r + j];
    for (int k = 0; k < j; ++k) pivot -= a[j * r + k] * a[j * r + k];
    if (!(pivot > 0.0)) return false;
    const double diagonal = std::sqrt(pivot);
    a[j * r + j] = diagonal;
    const double inverse = 1.0 / diagonal;
    for (int i = j + 1; i < r; ++i) {
      double value = a[i * r + j];
      for (int k = 0; k < j; ++k) value -= a[i * r + k] * a[j * r + k];
      a[i * r + j] = value * inverse;
    }
  }
  return true;
}

/// Overwrites b with A^-1 b from the factor of cholesky_in_place. Each substitution takes the
/// unknown found last as its last term, so a row's sum runs while the unknowns before it are
/// still being found (one chain of the row's length per unknown would wait on each other).
inline void cholesky_solve(std::span<const double> l, int r, std::span<double> b) noexcept {
  for (int i = 0; i < r; ++i) {
    double value = b[i];
    for (int k = 0; k < i; ++k) value -= l[i * r + k] * b[k];
    b[i] = value / l[i * r + i];
  }
  for (int i = r - 1; i >= 0; --i) {
    double value = b[i];
    for (int k = r - 1; k > i; --k) value -= l[k * r + i] * b[k];
    b[i] = value / l[i * r + i];
  }
}

}  // namespace nav::detail
