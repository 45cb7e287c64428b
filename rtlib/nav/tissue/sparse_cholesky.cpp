#include "nav/tissue/sparse_cholesky.hpp"

#include <Eigen/SparseCholesky>
#include <algorithm>
#include <vector>
#if NAV_CHOLMOD
#include <Eigen/CholmodSupport>
#include <mutex>
#endif

namespace nav {
namespace {

using SparseMatrix = Eigen::SparseMatrix<double>;

/// Factors `matrix` with `solver`, analysing its pattern first unless `analysed` is its pattern.
template <class Solver, class Pattern>
bool factor_with(Solver& solver, Pattern& analysed, const SparseMatrix& matrix) {
  if (!analysed.same_as(matrix)) {
    solver.analyzePattern(matrix);
    analysed.take(matrix);
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
  /// The sparsity pattern a solver analysed (compressed columns), empty before the first.
  struct Pattern {
    std::vector<int> column_starts, rows;

    bool same_as(const SparseMatrix& m) const {
      return m.isCompressed() && column_starts.size() == static_cast<std::size_t>(m.outerSize()) + 1 &&
             std::equal(column_starts.begin(), column_starts.end(), m.outerIndexPtr()) &&
             rows.size() == static_cast<std::size_t>(m.nonZeros()) &&
             std::equal(rows.begin(), rows.end(), m.innerIndexPtr());
    }
    void take(const SparseMatrix& m) {
      column_starts.assign(m.outerIndexPtr(), m.outerIndexPtr() + m.outerSize() + 1);
      rows.assign(m.innerIndexPtr(), m.innerIndexPtr() + (m.isCompressed() ? m.nonZeros() : 0));
    }
  };

#if NAV_CHOLMOD
  Eigen::CholmodSupernodalLLT<SparseMatrix, Eigen::Lower> llt;
  Pattern llt_analysed;
  bool positive_definite = false;
#endif
  Eigen::SimplicialLDLT<SparseMatrix, Eigen::Lower> ldlt;  // with CHOLMOD: what is not positive definite
  Pattern ldlt_analysed;
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

}  // namespace nav
