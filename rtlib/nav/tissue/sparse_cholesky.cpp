#include "nav/tissue/sparse_cholesky.hpp"

#include <Eigen/SparseCholesky>
#include <optional>
#include <utility>
#if NAV_CHOLMOD
#include <Eigen/CholmodSupport>
#include <mutex>
#endif

namespace nav {
namespace {

using SparseMatrix = Eigen::SparseMatrix<double>;
/// The size and stored entries of the matrix whose pattern a solver analysed.
using Shape = std::optional<std::pair<Eigen::Index, Eigen::Index>>;

/// Factors `matrix` with `solver`, analysing its pattern first unless `analysed` says the
/// solver holds the analysis of a matrix of this size and entry count.
template <class Solver>
bool factor_with(Solver& solver, Shape& analysed, const SparseMatrix& matrix) {
  const std::pair<Eigen::Index, Eigen::Index> shape{matrix.rows(), matrix.nonZeros()};
  if (analysed != shape) {
    solver.analyzePattern(matrix);
    analysed = shape;
  }
  solver.factorize(matrix);
  return solver.info() == Eigen::Success;
}

#if NAV_CHOLMOD
/// CHOLMOD's dense blocks run on the system's BLAS, which need not take calls from two threads
/// at once (Debian's serial OpenBLAS does not: two threads factoring at once got other bits
/// than one alone): one CHOLMOD factorisation or solve at a time in the process.
std::mutex& cholmod_calls() {
  static std::mutex calls;
  return calls;
}
#endif

}  // namespace

struct SparseCholesky::Factors {
#if NAV_CHOLMOD
  Eigen::CholmodSupernodalLLT<SparseMatrix, Eigen::Lower> llt;
  Shape llt_analysed;
  bool positive_definite = false;
#endif
  Eigen::SimplicialLDLT<SparseMatrix, Eigen::Lower> ldlt;  // with CHOLMOD: what is not positive definite
  Shape ldlt_analysed;
};

SparseCholesky::SparseCholesky() : factors_(std::make_unique<Factors>()) {
#if NAV_CHOLMOD
  factors_->llt.cholmod().print = 0;  // a matrix that is not positive definite is not an error here
#endif
}
SparseCholesky::~SparseCholesky() = default;
SparseCholesky::SparseCholesky(SparseCholesky&&) noexcept = default;
SparseCholesky& SparseCholesky::operator=(SparseCholesky&&) noexcept = default;

Status SparseCholesky::factor(const SparseMatrix& matrix, const char* field) {
  Factors& f = *factors_;
#if NAV_CHOLMOD
  {
    const std::lock_guard<std::mutex> one_at_a_time(cholmod_calls());
    f.positive_definite = factor_with(f.llt, f.llt_analysed, matrix);
  }
  if (f.positive_definite) return Done{};
#endif
  if (!factor_with(f.ldlt, f.ldlt_analysed, matrix))
    return Error{.message = "the sparse factorisation failed: the matrix is singular", .field = field};
  return Done{};
}

Eigen::VectorXd SparseCholesky::solve(const Eigen::VectorXd& rhs) const {
  const Factors& f = *factors_;
#if NAV_CHOLMOD
  if (f.positive_definite) {
    const std::lock_guard<std::mutex> one_at_a_time(cholmod_calls());
    return f.llt.solve(rhs);
  }
#endif
  return f.ldlt.solve(rhs);
}

const char* SparseCholesky::method() { return NAV_CHOLMOD ? "CHOLMOD supernodal LL^T" : "Eigen SimplicialLDLT"; }

}  // namespace nav
