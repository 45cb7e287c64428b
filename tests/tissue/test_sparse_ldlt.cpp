// SparseLdlt, the factor the full-order steps solve with, against dense algebra and Eigen's
// own factor: solves of a 3D grid system (whose eliminated separators make supernodes of
// many columns) as a dense LU's, every entry of Eigen's L kept, a matrix that is not positive
// definite refused with its field named, and a solve that allocates nothing.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/SparseCholesky>
#include <random>
#include <string>
#include <vector>

#include "nav/tissue/sparse_ldlt.hpp"
#include "support/allocation_guard.hpp"
#include "tissue/grid_matrix.hpp"

namespace nav {
namespace {

using SparseMatrix = Eigen::SparseMatrix<double>;
using testing::grid_matrix;

TEST(SparseLdlt, SolvesAGridSystemAsDenseAlgebraDoes) {
  const SparseMatrix a = grid_matrix(9, 0.05, 7);
  SparseLdlt ldlt;
  ASSERT_TRUE(ldlt.factor(a, "grid").ok());
  ASSERT_EQ(ldlt.size(), a.rows());
  // A quarter of the columns or more share a supernode with the one before: the dense blocks
  // are exercised.
  EXPECT_LT(ldlt.supernode_count(), ldlt.size() - ldlt.size() / 4);
  const Eigen::PartialPivLU<Eigen::MatrixXd> dense{Eigen::MatrixXd(a)};
  std::mt19937_64 rng(11);
  std::normal_distribution<double> normal;
  std::vector<double> work(static_cast<std::size_t>(ldlt.size()));
  for (int trial = 0; trial < 3; ++trial) {
    Eigen::VectorXd b(a.rows());
    for (Eigen::Index i = 0; i < b.size(); ++i) b[i] = normal(rng);
    const Eigen::VectorXd reference = dense.solve(b);
    Eigen::VectorXd x = b;
    ldlt.solve_in_place({x.data(), static_cast<std::size_t>(x.size())}, work);
    EXPECT_LT((x - reference).norm() / reference.norm(), 1e-12) << "right-hand side " << trial;
  }
}

TEST(SparseLdlt, KeepsEveryEntryOfEigensFactor) {
  const SparseMatrix a = grid_matrix(7, 0.1, 3);
  SparseLdlt ldlt;
  ASSERT_TRUE(ldlt.factor(a, "grid").ok());
  const Eigen::SimplicialLDLT<SparseMatrix, Eigen::Lower> reference(a);
  const SparseMatrix& l = reference.matrixL().nestedExpression();
  std::int64_t below = 0;
  for (Eigen::Index j = 0; j < l.outerSize(); ++j)
    for (SparseMatrix::InnerIterator it(l, j); it; ++it) below += it.row() > j ? 1 : 0;
  EXPECT_EQ(ldlt.factor_nonzeros(), below);
}

TEST(SparseLdlt, RefusesAMatrixThatIsNotPositiveDefinite) {
  SparseMatrix a = grid_matrix(4, 0.1, 2);
  a.coeffRef(5, 5) = -1.0;
  SparseLdlt ldlt;
  const Status status = ldlt.factor(a, "system");
  ASSERT_FALSE(status.ok());
  EXPECT_EQ(status.error().field, "system");
}

TEST(SparseLdlt, SolvesWithoutAllocating) {
  const SparseMatrix a = grid_matrix(6, 0.1, 5);
  SparseLdlt ldlt;
  ASSERT_TRUE(ldlt.factor(a, "grid").ok());
  std::vector<double> rhs(static_cast<std::size_t>(ldlt.size()), 1.0), work(rhs.size());
  const testing::AllocationGuard guard;
  ldlt.solve_in_place(rhs, work);
  EXPECT_EQ(guard.allocations(), 0u);
}

}  // namespace
}  // namespace nav
