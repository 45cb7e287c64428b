#include "nav/connective/banded_cholesky.hpp"

#include <algorithm>
#include <cmath>

namespace nav {

bool banded_cholesky_factor(std::span<double> band, std::size_t n, std::size_t b) noexcept {
  const std::size_t stride = b + 1;
  for (std::size_t j = 0; j < n; ++j) {
    double* column = band.data() + j * stride;
    if (!(column[0] > 0.0) || !std::isfinite(column[0])) return false;
    const double pivot = std::sqrt(column[0]);
    column[0] = pivot;
    const std::size_t last = std::min(n - 1, j + b);
    for (std::size_t i = j + 1; i <= last; ++i) column[i - j] /= pivot;
    for (std::size_t k = j + 1; k <= last; ++k) {
      const double l_kj = column[k - j];
      double* target = band.data() + k * stride;
      for (std::size_t i = k; i <= last; ++i) target[i - k] -= column[i - j] * l_kj;
    }
  }
  return true;
}

void banded_cholesky_solve(std::span<const double> factor, std::size_t n, std::size_t b, std::span<double> x) noexcept {
  const std::size_t stride = b + 1;
  for (std::size_t j = 0; j < n; ++j) {
    const double* column = factor.data() + j * stride;
    x[j] /= column[0];
    const std::size_t last = std::min(n - 1, j + b);
    for (std::size_t i = j + 1; i <= last; ++i) x[i] -= column[i - j] * x[j];
  }
  for (std::size_t j = n; j-- > 0;) {
    const double* column = factor.data() + j * stride;
    const std::size_t last = std::min(n - 1, j + b);
    double sum = x[j];
    for (std::size_t i = j + 1; i <= last; ++i) sum -= column[i - j] * x[i];
    x[j] = sum / column[0];
  }
}

}  // namespace nav
