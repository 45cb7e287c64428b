#pragma once
// A sparse LDL^T factorisation computed once at init (Eigen's SimplicialLDLT with AMD
// ordering) and kept as plain arrays in supernodes, so that step-time solves are
// allocation-free, visit the factor in a fixed order and stream it from memory.
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
  /// Supernodes: runs of columns whose rows below the run are one list, solved as dense blocks.
  std::int64_t supernode_count() const { return static_cast<std::int64_t>(supernode_columns_.size()) - 1; }
  /// Stored entries of L below the diagonal.
  std::int64_t factor_nonzeros() const { return static_cast<std::int64_t>(values_.size()); }
  /// Bytes the factor's arrays hold (values, row lists, supernode starts, permutation, D).
  std::int64_t memory_bytes() const {
    return static_cast<std::int64_t>(sizeof(double) * (values_.size() + diagonal_.size()) +
                                     sizeof(std::int32_t) *
                                         (rows_.size() + supernode_columns_.size() + supernode_values_.size() +
                                          supernode_rows_.size() + permutation_.size()));
  }

 private:
  void forward(std::span<double> z) const noexcept;
  void backward(std::span<double> y) const noexcept;

  std::vector<std::int32_t> permutation_;  // row i of A goes to row permutation_[i] of P A P^T
  // A supernode: columns c0 <= j < c1 of L whose rows below c1 are one list (each column's
  // rows the next column and that column's rows). Its values: the strictly lower triangle of
  // its diagonal block column by column, then the block below, row by row (w per row).
  std::vector<std::int32_t> supernode_columns_;  // c0 of each supernode, then the size
  std::vector<std::int32_t> supernode_values_;   // where each one's values start, then the count
  std::vector<std::int32_t> supernode_rows_;     // where each one's rows below start in rows_
  std::vector<std::int32_t> rows_;
  std::vector<double> values_;
  std::vector<double> diagonal_;
};

}  // namespace nav
