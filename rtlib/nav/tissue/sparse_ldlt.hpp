#pragma once
// A sparse LDL^T factorisation computed once at init (Eigen's SimplicialLDLT with AMD
// ordering) and kept as plain arrays, so that step-time solves are allocation-free and
// visit the factor in a fixed order.
#include <Eigen/Sparse>
#include <cstdint>
#include <span>
#include <vector>

#include "nav/core/error.hpp"

namespace nav {

/// P A P^T = L D L^T of a symmetric positive definite matrix, for repeated solves.
class SparseLdlt {
 public:
  /// Factors `matrix` (its lower triangle is read). Errors when it is not positive definite;
  /// `field` names the matrix in the Error.
  Status factor(const Eigen::SparseMatrix<double>& matrix, const char* field);

  /// Overwrites `rhs` with A^-1 rhs. `work` holds at least size() doubles. No allocation.
  void solve_in_place(std::span<double> rhs, std::span<double> work) const noexcept;

  std::int64_t size() const { return static_cast<std::int64_t>(diagonal_.size()); }
  /// Stored entries of L below the diagonal.
  std::int64_t factor_nonzeros() const { return static_cast<std::int64_t>(values_.size()); }
  /// Bytes the factor's arrays hold (values, row lists, column and row starts, permutation, D).
  std::int64_t memory_bytes() const {
    return static_cast<std::int64_t>(
        sizeof(double) * (values_.size() + diagonal_.size()) +
        sizeof(std::int32_t) * (rows_.size() + row_starts_.size() + column_starts_.size() + permutation_.size()));
  }

 private:
  std::vector<std::int32_t> permutation_;    // row i of A goes to row permutation_[i] of P A P^T
  std::vector<std::int32_t> column_starts_;  // L in compressed columns, unit diagonal left out
  std::vector<double> values_;
  // Column j's rows are rows_[row_starts_[j] ...], as many as its values: the columns of a
  // supernode (each column's rows the next column and that column's rows) share their first
  // column's list, so a solve reads a supernode's row indices once from memory.
  std::vector<std::int32_t> row_starts_;
  std::vector<std::int32_t> rows_;
  std::vector<double> diagonal_;
};

}  // namespace nav
