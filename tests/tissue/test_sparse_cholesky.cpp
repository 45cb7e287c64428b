// SparseCholesky, the factorisation of the offline solves, against dense algebra: a positive
// definite system (CHOLMOD's supernodal LL^T where the build has it), an indefinite one (the
// L D L^T fall-back), a second matrix of the same pattern (the kept ordering) or of another
// pattern with as many entries (analysed again), and a singular
// one (an Error naming the field); and two threads factoring and solving at once get the
// bits of one (the BLAS under CHOLMOD need not take concurrent calls).
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include "nav/tissue/sparse_cholesky.hpp"
#include "tissue/grid_matrix.hpp"

namespace nav {
namespace {

using SparseMatrix = Eigen::SparseMatrix<double>;
using testing::grid_matrix;

/// |x - A^-1 b| / |A^-1 b| with A^-1 b from a dense LU with pivoting.
double error_against_dense(const SparseMatrix& a, const Eigen::VectorXd& b, const Eigen::VectorXd& x) {
  const Eigen::VectorXd reference = Eigen::MatrixXd(a).fullPivLu().solve(b);
  return (x - reference).norm() / reference.norm();
}

TEST(SparseCholesky, SolvesAPositiveDefiniteSystemAsDenseAlgebraDoes) {
  const SparseMatrix a = grid_matrix(8, 0.1, 1);
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(a.rows(), -1.0, 2.0);
  SparseCholesky factor;
  ASSERT_TRUE(factor.factor(a, "a").ok());
  EXPECT_LT(error_against_dense(a, b, factor.solve(b)), 1e-12);
}

TEST(SparseCholesky, KeepsThePatternsOrderingForTheNextMatrixAndSolvesWithTheNewValues) {
  const SparseMatrix first = grid_matrix(6, 0.1, 1), second = grid_matrix(6, 2.0, 2);
  ASSERT_EQ(first.nonZeros(), second.nonZeros());
  const Eigen::VectorXd b = Eigen::VectorXd::Ones(first.rows());
  SparseCholesky factor;
  ASSERT_TRUE(factor.factor(first, "a").ok());
  ASSERT_TRUE(factor.factor(second, "a").ok());
  EXPECT_LT(error_against_dense(second, b, factor.solve(b)), 1e-12);
  EXPECT_GT(error_against_dense(first, b, factor.solve(b)), 1e-3);  // not the first matrix's answer
}

TEST(SparseCholesky, AnotherPatternWithAsManyEntriesIsAnalysedAgain) {
  const SparseMatrix first = grid_matrix(6, 0.1, 1);
  Eigen::VectorXi order(first.rows());
  for (Eigen::Index i = 0; i < order.size(); ++i)
    order[i] = static_cast<int>((7 * i) % order.size());  // 7 and 216 coprime
  const Eigen::PermutationMatrix<Eigen::Dynamic> permutation(order);
  SparseMatrix second;
  second = first.twistedBy(permutation);  // P A P^T: as many entries, elsewhere
  ASSERT_EQ(first.nonZeros(), second.nonZeros());
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(first.rows(), 0.5, 1.5);
  SparseCholesky factor;
  ASSERT_TRUE(factor.factor(first, "a").ok());
  ASSERT_TRUE(factor.factor(second, "a").ok());
  EXPECT_LT(error_against_dense(second, b, factor.solve(b)), 1e-12);
}

TEST(SparseCholesky, SolvesAnIndefiniteSystemThroughItsLdlt) {
  // A negative shift below the Laplacian's smallest eigenvalue and above its next: one
  // negative pivot, no zero one.
  const SparseMatrix laplacian = grid_matrix(5, 0.0, 3);
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> spectrum{Eigen::MatrixXd(laplacian)};
  const double between = 0.5 * (spectrum.eigenvalues()[0] + spectrum.eigenvalues()[1]);
  SparseMatrix identity(laplacian.rows(), laplacian.cols());
  identity.setIdentity();
  const SparseMatrix a = laplacian - between * identity;
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(a.rows(), 1.0, 3.0);
  SparseCholesky factor;
  ASSERT_TRUE(factor.factor(a, "a").ok());
  EXPECT_LT(error_against_dense(a, b, factor.solve(b)), 1e-9);
}

TEST(SparseCholesky, TwoThreadsFactoringAndSolvingAtOnceGetTheBitsOfOne) {
  const SparseMatrix a = grid_matrix(18, 0.1, 5);  // large enough for dense supernodal blocks
  const Eigen::VectorXd b = Eigen::VectorXd::LinSpaced(a.rows(), -1.0, 1.0);
  const auto solved = [&](int rounds) {
    Eigen::VectorXd x;
    for (int k = 0; k < rounds; ++k) {
      SparseCholesky factor;
      if (!factor.factor(a, "a").ok()) return Eigen::VectorXd();
      x = factor.solve(b);
    }
    return x;
  };
  const Eigen::VectorXd alone = solved(1);
  ASSERT_EQ(alone.size(), a.rows());
  Eigen::VectorXd together[2];
  std::thread other([&] { together[1] = solved(6); });
  together[0] = solved(6);
  other.join();
  for (const Eigen::VectorXd& x : together) {
    ASSERT_EQ(x.size(), alone.size());
    EXPECT_EQ(std::memcmp(x.data(), alone.data(), sizeof(double) * static_cast<std::size_t>(x.size())), 0);
  }
}

TEST(SparseCholesky, ASingularMatrixIsAnErrorNamingItsField) {
  // A positive definite block beside an unknown that nothing holds (a zero pivot).
  const SparseMatrix block = grid_matrix(4, 1.0, 4);
  std::vector<Eigen::Triplet<double>> entries;
  for (Eigen::Index k = 0; k < block.outerSize(); ++k)
    for (SparseMatrix::InnerIterator it(block, k); it; ++it) entries.emplace_back(it.row(), it.col(), it.value());
  entries.emplace_back(block.rows(), block.rows(), 0.0);
  SparseMatrix a(block.rows() + 1, block.rows() + 1);
  a.setFromTriplets(entries.begin(), entries.end());
  SparseCholesky factor;
  const Status factored = factor.factor(a, "tangent");
  ASSERT_FALSE(factored.ok());
  EXPECT_EQ(factored.error().field, "tangent");
  EXPECT_NE(factored.error().message.find("singular"), std::string::npos) << factored.error().message;
}

}  // namespace
}  // namespace nav
