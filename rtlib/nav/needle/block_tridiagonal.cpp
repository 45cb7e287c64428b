#include "nav/needle/block_tridiagonal.hpp"

#include <Eigen/Core>
#include <cmath>
#include <cstddef>

namespace nav {

namespace {

using Block = Eigen::Map<Eigen::Matrix<double, 6, 6>>;
using ConstBlock = Eigen::Map<const Eigen::Matrix<double, 6, 6>>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;

std::size_t at(int k) { return 36 * static_cast<std::size_t>(k); }

/// The inverse of a symmetric positive definite 6x6 matrix through its Cholesky factor, by
/// fixed-size loops (Eigen's general triangular solves cost more than the arithmetic here),
/// dividing only for the reciprocals of the factor's diagonal: the chains of the
/// substitutions then run through multiplications. False when the matrix is not positive
/// definite.
bool spd_inverse(const Matrix6d& s, Matrix6d& inverse) {
  double g[6][6] = {};  // s = g g^T, g lower; its diagonal is kept as reciprocals in r
  double r[6] = {};
#pragma GCC unroll 6
  for (int j = 0; j < 6; ++j) {
    double d = s(j, j);
    for (int k = 0; k < j; ++k) d -= g[j][k] * g[j][k];
    if (!(d > 0.0)) return false;
    r[j] = 1.0 / std::sqrt(d);
#pragma GCC unroll 6
    for (int i = j + 1; i < 6; ++i) {
      double v = s(i, j);
      for (int k = 0; k < j; ++k) v -= g[i][k] * g[j][k];
      g[i][j] = v * r[j];
    }
  }
  double h[6][6] = {};  // h = g^-1, lower
#pragma GCC unroll 6
  for (int j = 0; j < 6; ++j) {
    h[j][j] = r[j];
#pragma GCC unroll 6
    for (int i = j + 1; i < 6; ++i) {
      double v = 0.0;
      for (int k = j; k < i; ++k) v -= g[i][k] * h[k][j];
      h[i][j] = v * r[i];
    }
  }
  // s^-1 = h^T h, symmetric by construction.
#pragma GCC unroll 6
  for (int j = 0; j < 6; ++j)
#pragma GCC unroll 6
    for (int i = j; i < 6; ++i) {
      double v = 0.0;
      for (int k = i; k < 6; ++k) v += h[k][i] * h[k][j];
      inverse(i, j) = inverse(j, i) = v;
    }
  return true;
}

}  // namespace

bool factor_block_tridiagonal(BlockTridiagonal& m) noexcept {
  for (int k = 0; k < m.blocks; ++k) {
    Matrix6d s = ConstBlock(m.diagonal.data() + at(k));
    if (k > 0) {
      const ConstBlock previous_upper(m.upper.data() + at(k - 1));
      const Matrix6d y = ConstBlock(m.schur.data() + at(k - 1)) * previous_upper;  // S_k-1^-1 A_k-1,k
      Block(m.multiplier.data() + at(k)).noalias() = y.transpose();
      s.noalias() -= previous_upper.transpose() * y;
    }
    Matrix6d inverse;
    if (!spd_inverse(s, inverse)) return false;
    Block(m.schur.data() + at(k)) = inverse;
  }
  return true;
}

void solve_block_tridiagonal(const BlockTridiagonal& m, std::span<double> rhs) noexcept {
  using Segment = Eigen::Map<Eigen::Matrix<double, 6, 1>>;
  using Vector6d = Eigen::Matrix<double, 6, 1>;
  for (int k = 1; k < m.blocks; ++k)
    Segment(rhs.data() + 6 * k).noalias() -=
        ConstBlock(m.multiplier.data() + at(k)) * Segment(rhs.data() + 6 * (k - 1));
  for (int k = 0; k < m.blocks; ++k) {
    Segment y(rhs.data() + 6 * k);
    const Vector6d b = y;
    y.noalias() = ConstBlock(m.schur.data() + at(k)) * b;
  }
  for (int k = m.blocks - 2; k >= 0; --k)
    Segment(rhs.data() + 6 * k).noalias() -=
        ConstBlock(m.multiplier.data() + at(k + 1)).transpose() * Segment(rhs.data() + 6 * (k + 1));
}

void translational_inverse_blocks(const BlockTridiagonal& m, int first, std::span<double> diagonal_work,
                                  std::span<double> column_work, std::span<double> out,
                                  std::size_t out_stride) noexcept {
  using DenseBlock = Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>, 0, Eigen::OuterStride<>>;
  const auto block_at = [&](int i, int j) {
    return DenseBlock(out.data() + 3 * static_cast<std::size_t>(i) * out_stride + 3 * static_cast<std::size_t>(j),
                      Eigen::OuterStride<>(static_cast<Eigen::Index>(out_stride)));
  };
  using Column = Eigen::Map<Eigen::Matrix<double, 6, 3>>;
  const int n = m.blocks;
  // Diagonal blocks of the inverse, bottom up: Sigma_kk = S_k^-1 - L_k+1^T Sigma_k+1,k.
  for (int k = n - 1; k >= first; --k) {
    Matrix6d inverse = ConstBlock(m.schur.data() + at(k));
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
    Column(column_work.data() + 18 * static_cast<std::size_t>(j)) =
        ConstBlock(diagonal_work.data() + at(j)).leftCols<3>();
    for (int i = j - 1; i >= first; --i)
      Column(column_work.data() + 18 * static_cast<std::size_t>(i)).noalias() =
          -ConstBlock(m.multiplier.data() + at(i + 1)).transpose() *
          Column(column_work.data() + 18 * static_cast<std::size_t>(i + 1));
    for (int i = first; i <= j; ++i) {
      const Eigen::Matrix3d block = Column(column_work.data() + 18 * static_cast<std::size_t>(i)).topRows<3>();
      block_at(i, j) = block;
      block_at(j, i) = block.transpose();
    }
  }
}

}  // namespace nav
