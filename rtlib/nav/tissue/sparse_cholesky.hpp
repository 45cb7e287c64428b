#pragma once
// The sparse factorisation of the init-time and offline solves (static equilibria, the reduced
// liver's training, shift-invert eigenproblems): CHOLMOD's supernodal LL^T where the build has
// SuiteSparse (NAV_CHOLMOD, its dense blocks on the system's BLAS: OpenBLAS from
// toolchain/install-deps.sh), Eigen's SimplicialLDLT otherwise (the rtlib-only and aarch64
// builds). It allocates: the step functions solve with SparseLdlt.
#include <Eigen/SparseCore>
#include <memory>

#include "nav/core/error.hpp"

namespace nav {

/// A symmetric matrix factored once and solved with many times.
class SparseCholesky {
 public:
  SparseCholesky();
  ~SparseCholesky();
  SparseCholesky(SparseCholesky&&) noexcept;
  SparseCholesky& operator=(SparseCholesky&&) noexcept;

  /// Factors the symmetric matrix whose lower triangle `matrix` holds. The fill-reducing
  /// ordering is kept for the next matrices of the same sparsity pattern (a Newton solve's
  /// tangents). A matrix that is not positive definite is factored
  /// as L D L^T (Eigen's). Errors, naming `field`: a singular matrix.
  Status factor(const Eigen::SparseMatrix<double>& matrix, const char* field);

  /// A^-1 rhs with the last matrix factored.
  Eigen::VectorXd solve(const Eigen::VectorXd& rhs) const;

 private:
  struct Factors;
  std::unique_ptr<Factors> factors_;
};

}  // namespace nav
