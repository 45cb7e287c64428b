#include "nav/tissue/sparse_ldlt.hpp"

#include <Eigen/SparseCholesky>
#include <algorithm>
#include <utility>

namespace nav {

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
  column_starts_.assign(1, 0);
  values_.clear();
  row_starts_.clear();
  rows_.clear();
  std::vector<std::int32_t> column, previous;  // rows of column j, and of column j - 1
  for (Eigen::Index j = 0; j < l.outerSize(); ++j) {
    column.clear();
    for (Eigen::SparseMatrix<double>::InnerIterator it(l, j); it; ++it) {
      if (it.row() <= j) continue;
      column.push_back(static_cast<std::int32_t>(it.row()));
      values_.push_back(it.value());
    }
    column_starts_.push_back(static_cast<std::int32_t>(values_.size()));
    const bool continues_supernode = j > 0 && previous.size() == column.size() + 1 && previous.front() == j &&
                                     std::equal(column.begin(), column.end(), previous.begin() + 1);
    if (continues_supernode) {
      row_starts_.push_back(row_starts_.back() + 1);
    } else {
      row_starts_.push_back(static_cast<std::int32_t>(rows_.size()));
      rows_.insert(rows_.end(), column.begin(), column.end());
    }
    std::swap(column, previous);
  }
  return Done{};
}

void SparseLdlt::solve_in_place(std::span<double> rhs, std::span<double> work) const noexcept {
  const std::size_t n = diagonal_.size();
  for (std::size_t i = 0; i < n; ++i) work[static_cast<std::size_t>(permutation_[i])] = rhs[i];
  for (std::size_t j = 0; j < n; ++j) {  // L z = P b
    const double zj = work[j];
    const std::int32_t shift = row_starts_[j] - column_starts_[j];  // value k's row is rows_[k + shift]
    for (std::int32_t k = column_starts_[j]; k < column_starts_[j + 1]; ++k) work[rows_[k + shift]] -= values_[k] * zj;
  }
  for (std::size_t j = 0; j < n; ++j) work[j] /= diagonal_[j];
  for (std::size_t j = n; j-- > 0;) {  // L^T y = z
    double sum = work[j];
    const std::int32_t shift = row_starts_[j] - column_starts_[j];
    for (std::int32_t k = column_starts_[j]; k < column_starts_[j + 1]; ++k) sum -= values_[k] * work[rows_[k + shift]];
    work[j] = sum;
  }
  for (std::size_t i = 0; i < n; ++i) rhs[i] = work[static_cast<std::size_t>(permutation_[i])];
}

}  // namespace nav
