#include "nav/tissue/tet_kernels.hpp"

#include <cmath>

namespace nav {

Matrix43 shape_gradients(const std::array<Point3, 4>& corners_m) {
  Eigen::Matrix3d edges;
  for (int k = 0; k < 3; ++k)
    for (int r = 0; r < 3; ++r) edges(r, k) = corners_m[k + 1][r] - corners_m[0][r];
  const Eigen::Matrix3d inverse = edges.inverse();  // rows: gradients of vertices 1..3
  Matrix43 gradients;
  gradients.bottomRows<3>() = inverse;
  gradients.row(0) = -inverse.colwise().sum();
  return gradients;
}

Matrix6x12 strain_displacement(const Matrix43& gradients) {
  Matrix6x12 b = Matrix6x12::Zero();
  for (int a = 0; a < 4; ++a) {
    const double gx = gradients(a, 0), gy = gradients(a, 1), gz = gradients(a, 2);
    b(0, 3 * a) = gx;
    b(1, 3 * a + 1) = gy;
    b(2, 3 * a + 2) = gz;
    b(3, 3 * a) = gy;
    b(3, 3 * a + 1) = gx;
    b(4, 3 * a + 1) = gz;
    b(4, 3 * a + 2) = gy;
    b(5, 3 * a) = gz;
    b(5, 3 * a + 2) = gx;
  }
  return b;
}

Matrix6 elasticity_matrix(const LameParameters& lame) {
  Matrix6 d = Matrix6::Zero();
  d.topLeftCorner<3, 3>().setConstant(lame.lambda_pa);
  const double axial = lame.lambda_pa + 2.0 * lame.mu_pa;
  d.diagonal() << axial, axial, axial, lame.mu_pa, lame.mu_pa, lame.mu_pa;
  return d;
}

Matrix12 element_stiffness(const Matrix43& gradients, const LameParameters& lame, double volume_m3) {
  const Matrix6x12 b = strain_displacement(gradients);
  const Matrix6x12 db = elasticity_matrix(lame) * b;
  Matrix12 k;
  k.noalias() = volume_m3 * (b.transpose() * db);
  return k;
}

namespace {

/// One scaled Newton iteration of the polar decomposition on every lane, in place; with kTrack,
/// each lane's largest entry change into `change`.
template <bool kTrack>
void polar_iteration(PolarBatch& batch, std::array<double, kPolarLanes>& change) noexcept {
  for (int l = 0; l < kPolarLanes; ++l) {
    const double a00 = batch[0][l], a10 = batch[1][l], a20 = batch[2][l];
    const double a01 = batch[3][l], a11 = batch[4][l], a21 = batch[5][l];
    const double a02 = batch[6][l], a12 = batch[7][l], a22 = batch[8][l];
    // Cofactors: R^-T = cofactor / det.
    const double c00 = a11 * a22 - a12 * a21, c01 = a12 * a20 - a10 * a22, c02 = a10 * a21 - a11 * a20;
    const double c10 = a02 * a21 - a01 * a22, c11 = a00 * a22 - a02 * a20, c12 = a01 * a20 - a00 * a21;
    const double c20 = a01 * a12 - a02 * a11, c21 = a02 * a10 - a00 * a12, c22 = a00 * a11 - a01 * a10;
    const double det = a00 * c00 + a01 * c01 + a02 * c02;
    const double norm_a =
        a00 * a00 + a10 * a10 + a20 * a20 + a01 * a01 + a11 * a11 + a21 * a21 + a02 * a02 + a12 * a12 + a22 * a22;
    const double norm_c =
        c00 * c00 + c10 * c10 + c20 * c20 + c01 * c01 + c11 * c11 + c21 * c21 + c02 * c02 + c12 * c12 + c22 * c22;
    // g^4 = |R^-T|^2 / |R|^2; R <- (g R + cofactor / (g det)) / 2.
    const double scale = std::sqrt(std::sqrt(norm_c / (det * det * norm_a)));
    const double own = 0.5 * scale, inverse = 0.5 / (scale * det);
    batch[0][l] = own * a00 + inverse * c00;
    batch[1][l] = own * a10 + inverse * c10;
    batch[2][l] = own * a20 + inverse * c20;
    batch[3][l] = own * a01 + inverse * c01;
    batch[4][l] = own * a11 + inverse * c11;
    batch[5][l] = own * a21 + inverse * c21;
    batch[6][l] = own * a02 + inverse * c02;
    batch[7][l] = own * a12 + inverse * c12;
    batch[8][l] = own * a22 + inverse * c22;
    if constexpr (kTrack) {
      const double before[9] = {a00, a10, a20, a01, a11, a21, a02, a12, a22};
      double largest = 0.0;
      for (int k = 0; k < 9; ++k) largest = std::max(largest, std::abs(batch[k][l] - before[k]));
      change[l] = largest;
    }
  }
}

}  // namespace

void polar_rotations(PolarBatch& batch) noexcept {
  std::array<double, kPolarLanes> change{};
  for (int iteration = 1; iteration < kPolarFirstIterations; ++iteration) polar_iteration<false>(batch, change);
  polar_iteration<true>(batch, change);
  // The rare lanes not converged yet go on alone: the others are put back after each iteration.
  std::array<bool, kPolarLanes> converged{};
  for (int l = 0; l < kPolarLanes; ++l) converged[l] = change[l] <= kPolarConvergedChange;
  for (int iteration = kPolarFirstIterations; iteration < kPolarIterations; ++iteration) {
    if (std::all_of(converged.begin(), converged.end(), [](bool done) { return done; })) break;
    const PolarBatch before = batch;
    polar_iteration<true>(batch, change);
    for (int l = 0; l < kPolarLanes; ++l) {
      for (int k = 0; k < 9; ++k) batch[k][l] = converged[l] ? before[k][l] : batch[k][l];
      converged[l] = converged[l] || change[l] <= kPolarConvergedChange;
    }
  }
}

Eigen::Matrix3d polar_rotation(const Eigen::Matrix3d& f) {
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  for_each_polar_rotation(
      1,
      [&](std::size_t, Eigen::Matrix3d& out) {
        out = f;
        return true;
      },
      [&](std::size_t, const Eigen::Matrix3d& r) { rotation = r; });
  return rotation;
}

}  // namespace nav
