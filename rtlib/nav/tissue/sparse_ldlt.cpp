#include "nav/tissue/sparse_ldlt.hpp"

#include <Eigen/SparseCholesky>
#include <algorithm>
#include <utility>

namespace nav {
namespace {

using Index = std::size_t;

Index index(std::int32_t value) { return static_cast<Index>(value); }

/// Rows a forward pass updates together: independent sums that overlap each other's latency.
constexpr Index kRowsTogether = 8;

}  // namespace

Status SparseLdlt::factor(const Eigen::SparseMatrix<double>& matrix, const char* field) {
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower> ldlt(matrix);
  if (ldlt.info() != Eigen::Success) return Error{.message = "the sparse LDL^T factorisation failed", .field = field};
  const Eigen::VectorXd d = ldlt.vectorD();
  for (Eigen::Index i = 0; i < d.size(); ++i)
    if (!(d[i] > 0.0))
      return Error{.message = "the matrix is not positive definite (rigid motions left free?)", .field = field};
  const Eigen::SparseMatrix<double>& l = ldlt.matrixL().nestedExpression();  // strictly lower part is L
  permutation_.assign(ldlt.permutationP().indices().data(), ldlt.permutationP().indices().data() + d.size());
  diagonal_.assign(d.data(), d.data() + d.size());
  // Each column's rows below the diagonal and their values, in order.
  const auto n = static_cast<std::int32_t>(d.size());
  std::vector<std::vector<std::int32_t>> column_rows(index(n));
  std::vector<std::vector<double>> column_values(index(n));
  for (std::int32_t j = 0; j < n; ++j)
    for (Eigen::SparseMatrix<double>::InnerIterator it(l, j); it; ++it)
      if (it.row() > j) {
        column_rows[index(j)].push_back(static_cast<std::int32_t>(it.row()));
        column_values[index(j)].push_back(it.value());
      }
  supernode_columns_.clear();
  supernode_values_.clear();
  supernode_rows_.clear();
  rows_.clear();
  values_.clear();
  for (std::int32_t c0 = 0; c0 < n;) {
    std::int32_t c1 = c0 + 1;
    while (c1 < n) {
      const std::vector<std::int32_t>& previous = column_rows[index(c1 - 1)];
      const std::vector<std::int32_t>& column = column_rows[index(c1)];
      if (previous.size() != column.size() + 1 || previous.front() != c1 ||
          !std::equal(column.begin(), column.end(), previous.begin() + 1))
        break;
      ++c1;
    }
    const Index w = index(c1 - c0);
    supernode_columns_.push_back(c0);
    supernode_values_.push_back(static_cast<std::int32_t>(values_.size()));
    supernode_rows_.push_back(static_cast<std::int32_t>(rows_.size()));
    for (Index j = 0; j < w; ++j) {  // the diagonal block's strictly lower triangle, by columns
      const std::vector<double>& values = column_values[index(c0) + j];
      values_.insert(values_.end(), values.begin(), values.begin() + static_cast<std::ptrdiff_t>(w - 1 - j));
    }
    const std::vector<std::int32_t>& first = column_rows[index(c0)];
    const Index below = first.size() - (w - 1);
    rows_.insert(rows_.end(), first.begin() + static_cast<std::ptrdiff_t>(w - 1), first.end());
    for (Index r = 0; r < below; ++r)  // the block below, by rows
      for (Index j = 0; j < w; ++j) values_.push_back(column_values[index(c0) + j][w - 1 - j + r]);
    c0 = c1;
  }
  supernode_columns_.push_back(n);
  supernode_values_.push_back(static_cast<std::int32_t>(values_.size()));
  supernode_rows_.push_back(static_cast<std::int32_t>(rows_.size()));
  return Done{};
}

/// L z = b in place: a supernode's triangle column by column, then each row below takes its
/// w terms in column order (the order of a column-by-column pass, so the same bits).
void SparseLdlt::forward(std::span<double> z) const noexcept {
  const Index supernodes = supernode_columns_.size() - 1;
  for (Index s = 0; s < supernodes; ++s) {
    const Index c0 = index(supernode_columns_[s]), w = index(supernode_columns_[s + 1]) - c0;
    const double* v = values_.data() + index(supernode_values_[s]);
    double* zs = z.data() + c0;
    for (Index j = 0; j < w; ++j)
      for (Index i = j + 1; i < w; ++i) zs[i] -= *v++ * zs[j];
    const std::int32_t* rows = rows_.data() + index(supernode_rows_[s]);
    const Index below = index(supernode_rows_[s + 1] - supernode_rows_[s]);
    Index r = 0;
    for (; r + kRowsTogether <= below; r += kRowsTogether) {
      double t[kRowsTogether];
      for (Index k = 0; k < kRowsTogether; ++k) t[k] = z[index(rows[r + k])];
      for (Index j = 0; j < w; ++j)
        for (Index k = 0; k < kRowsTogether; ++k) t[k] -= v[k * w + j] * zs[j];
      for (Index k = 0; k < kRowsTogether; ++k) z[index(rows[r + k])] = t[k];
      v += kRowsTogether * w;
    }
    for (; r < below; ++r, v += w) {
      double t = z[index(rows[r])];
      for (Index j = 0; j < w; ++j) t -= v[j] * zs[j];
      z[index(rows[r])] = t;
    }
  }
}

/// L^T y = z in place, supernodes from the last: each column takes its terms from the rows
/// below first (a row at a time, across the supernode's columns), then from its triangle.
void SparseLdlt::backward(std::span<double> y) const noexcept {
  for (Index s = supernode_columns_.size() - 1; s-- > 0;) {
    const Index c0 = index(supernode_columns_[s]), w = index(supernode_columns_[s + 1]) - c0;
    const double* triangle = values_.data() + index(supernode_values_[s]);
    const double* v = triangle + w * (w - 1) / 2;  // the block below
    double* ys = y.data() + c0;
    const std::int32_t* rows = rows_.data() + index(supernode_rows_[s]);
    const Index below = index(supernode_rows_[s + 1] - supernode_rows_[s]);
    for (Index r = 0; r < below; ++r, v += w) {
      const double yr = y[index(rows[r])];
      for (Index j = 0; j < w; ++j) ys[j] -= v[j] * yr;
    }
    for (Index j = w; j-- > 0;) {
      const double* column = triangle + j * (2 * w - j - 1) / 2;  // rows j + 1 ... w - 1
      double sum = ys[j];
      for (Index i = j + 1; i < w; ++i) sum -= column[i - j - 1] * ys[i];
      ys[j] = sum;
    }
  }
}

void SparseLdlt::solve_in_place(std::span<double> rhs, std::span<double> work) const noexcept {
  const std::size_t n = diagonal_.size();
  for (std::size_t i = 0; i < n; ++i) work[static_cast<std::size_t>(permutation_[i])] = rhs[i];
  forward(work);
  for (std::size_t j = 0; j < n; ++j) work[j] /= diagonal_[j];
  backward(work);
  for (std::size_t i = 0; i < n; ++i) rhs[i] = work[static_cast<std::size_t>(permutation_[i])];
}

}  // namespace nav
