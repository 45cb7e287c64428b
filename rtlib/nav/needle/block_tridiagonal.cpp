#include "nav/needle/block_tridiagonal.hpp"

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <cstddef>

namespace nav {

namespace {

using Block = Eigen::Map<Eigen::Matrix<double, 6, 6>>;
using ConstBlock = Eigen::Map<const Eigen::Matrix<double, 6, 6>>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;

std::size_t at(int k) { return 36 * static_cast<std::size_t>(k); }

/// Y := S^-1 Y with S = G G^T, G the stored lower factor.
template <typename Rhs>
void schur_solve(const double* factor, Rhs&& y) {
  const ConstBlock g(factor);
  g.triangularView<Eigen::Lower>().solveInPlace(y);
  g.transpose().triangularView<Eigen::Upper>().solveInPlace(y);
}

}  // namespace

bool factor_block_tridiagonal(BlockTridiagonal& m) noexcept {
  for (int k = 0; k < m.blocks; ++k) {
    Matrix6d s = ConstBlock(m.diagonal.data() + at(k));
    if (k > 0) {
      const ConstBlock previous_upper(m.upper.data() + at(k - 1));
      Matrix6d y = previous_upper;  // S_k-1^-1 A_k-1,k
      schur_solve(m.schur.data() + at(k - 1), y);
      Block multiplier(m.multiplier.data() + at(k));
      multiplier.noalias() = y.transpose();
      s.noalias() -= previous_upper.transpose() * y;
    }
    const Eigen::LLT<Matrix6d> llt(s);
    if (llt.info() != Eigen::Success) return false;
    Block(m.schur.data() + at(k)) = llt.matrixLLT();
  }
  return true;
}

void solve_block_tridiagonal(const BlockTridiagonal& m, std::span<double> rhs) noexcept {
  using Segment = Eigen::Map<Eigen::Matrix<double, 6, 1>>;
  for (int k = 1; k < m.blocks; ++k)
    Segment(rhs.data() + 6 * k).noalias() -= ConstBlock(m.multiplier.data() + at(k)) * Segment(rhs.data() + 6 * (k - 1));
  for (int k = 0; k < m.blocks; ++k) {
    Segment y(rhs.data() + 6 * k);
    schur_solve(m.schur.data() + at(k), y);
  }
  for (int k = m.blocks - 2; k >= 0; --k)
    Segment(rhs.data() + 6 * k).noalias() -=
        ConstBlock(m.multiplier.data() + at(k + 1)).transpose() * Segment(rhs.data() + 6 * (k + 1));
}

void translational_inverse_blocks(const BlockTridiagonal& m, int first, std::span<double> diagonal_work,
                                  std::span<double> column_work, std::span<double> out) noexcept {
  using Column = Eigen::Map<Eigen::Matrix<double, 6, 3>>;
  const int n = m.blocks;
  // Diagonal blocks of the inverse, bottom up: Sigma_kk = S_k^-1 - L_k+1^T Sigma_k+1,k.
  for (int k = n - 1; k >= first; --k) {
    Matrix6d inverse = Matrix6d::Identity();
    schur_solve(m.schur.data() + at(k), inverse);
    if (k + 1 < n) {
      const ConstBlock next_multiplier(m.multiplier.data() + at(k + 1));
      const Matrix6d below = ConstBlock(diagonal_work.data() + at(k + 1));
      // Sigma_k+1,k = -Sigma_k+1,k+1 L_k+1
      const Matrix6d coupling = -below * next_multiplier;
      inverse.noalias() -= next_multiplier.transpose() * coupling;
    }
    Block(diagonal_work.data() + at(k)) = inverse;
  }
  // Columns: Sigma_ij[:, 0:3] = -L_i+1^T Sigma_i+1,j[:, 0:3] for i < j.
  for (int j = first; j < n; ++j) {
    Column(column_work.data() + 18 * static_cast<std::size_t>(j)) = ConstBlock(diagonal_work.data() + at(j)).leftCols<3>();
    for (int i = j - 1; i >= first; --i)
      Column(column_work.data() + 18 * static_cast<std::size_t>(i)).noalias() =
          -ConstBlock(m.multiplier.data() + at(i + 1)).transpose() * Column(column_work.data() + 18 * static_cast<std::size_t>(i + 1));
    for (int i = first; i <= j; ++i) {
      const Eigen::Matrix3d block = Column(column_work.data() + 18 * static_cast<std::size_t>(i)).topRows<3>();
      Eigen::Map<Eigen::Matrix3d>(out.data() + 9 * (static_cast<std::size_t>(i) * n + j)) = block;
      Eigen::Map<Eigen::Matrix3d>(out.data() + 9 * (static_cast<std::size_t>(j) * n + i)) = block.transpose();
    }
  }
}

}  // namespace nav
