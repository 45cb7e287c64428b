#include "nav/needle/beam_element.hpp"

#include "nav/needle/rotation_vector.hpp"

namespace nav {

Matrix12d beam_local_stiffness(const NeedleParameters& p, const NeedleSection& s, double l) {
  const double E = p.youngs_modulus_pa, G = s.shear_modulus_pa, I = s.second_moment_m4;
  const double phi =
      p.theory == BeamTheory::timoshenko ? 12.0 * E * I / (G * s.shear_coefficient * s.area_m2 * l * l) : 0.0;
  Matrix12d k = Matrix12d::Zero();
  const double axial = E * s.area_m2 / l, torsion = G * s.polar_moment_m4 / l;
  k(0, 0) = k(6, 6) = axial;
  k(0, 6) = -axial;
  k(3, 3) = k(9, 9) = torsion;
  k(3, 9) = -torsion;
  const double c = E * I / ((1.0 + phi) * l * l * l);
  // Bending in the local xy plane: v with theta_z.
  k(1, 1) = k(7, 7) = 12.0 * c;
  k(1, 7) = -12.0 * c;
  k(1, 5) = k(1, 11) = 6.0 * l * c;
  k(5, 7) = k(7, 11) = -6.0 * l * c;
  k(5, 5) = k(11, 11) = (4.0 + phi) * l * l * c;
  k(5, 11) = (2.0 - phi) * l * l * c;
  // Bending in the local xz plane: w with theta_y (opposite coupling sign).
  k(2, 2) = k(8, 8) = 12.0 * c;
  k(2, 8) = -12.0 * c;
  k(2, 4) = k(2, 10) = -6.0 * l * c;
  k(4, 8) = k(8, 10) = 6.0 * l * c;
  k(4, 4) = k(10, 10) = (4.0 + phi) * l * l * c;
  k(4, 10) = (2.0 - phi) * l * l * c;
  for (int i = 0; i < 12; ++i)
    for (int j = 0; j < i; ++j) k(i, j) = k(j, i);
  return k;
}

namespace {

/// The freedoms a corotational deformation moves, in order: theta_a, the stretch, theta_b.
constexpr std::array<int, BeamStiffness::kMovedFreedoms> kMovedFreedomIndices = {3, 4, 5, 6, 9, 10, 11};

/// The ten tangent blocks as (row, column) of their top-left entry in the local stiffness:
/// aa's (0, 0), (0, 1), (1, 1); ab's (0, 2), (0, 3), (1, 2), (1, 3); bb's (2, 2), (2, 3), (3, 3).
constexpr std::array<std::array<int, 2>, BeamStiffness::kTangentBlocks> kTangentBlocks = {
    {{0, 0}, {0, 3}, {3, 3}, {0, 6}, {0, 9}, {3, 6}, {3, 9}, {6, 6}, {6, 9}, {9, 9}}};

/// The three coefficients rotated_block() reads of the block at (row, col).
std::array<double, 3> block_coefficients(const Matrix12d& k, int row, int col) {
  return {k(row, col), k(row + 1, col + 1), k(row + 1, col + 2)};
}

}  // namespace

BeamStiffness beam_stiffness(const Matrix12d& local) {
  BeamStiffness s;
  s.local = local;
  for (std::size_t i = 0; i < 12; ++i)
    for (int j : kMovedFreedomIndices) {
      const double value = local(static_cast<Eigen::Index>(i), j);
      if (value != 0.0) s.force_terms[i][static_cast<std::size_t>(s.force_term_count[i]++)] = {j, value};
    }
  for (std::size_t b = 0; b < kTangentBlocks.size(); ++b) {
    std::size_t first = 0;
    while (block_coefficients(local, kTangentBlocks[first][0], kTangentBlocks[first][1]) !=
           block_coefficients(local, kTangentBlocks[b][0], kTangentBlocks[b][1]))
      ++first;
    s.same_block_as[b] = static_cast<int>(first);
  }
  return s;
}

namespace {

/// The element frame's two products that every rotated block of the local stiffness uses:
/// e1 e1^T and e2 e3^T - e3 e2^T.
struct FrameProducts {
  Eigen::Matrix3d axial, twist;
};

FrameProducts frame_products(const Eigen::Matrix3d& frame) {
  const Eigen::Vector3d e1 = frame.col(0), e2 = frame.col(1), e3 = frame.col(2);
  return {e1 * e1.transpose(), e2 * e3.transpose() - e3 * e2.transpose()};
}

/// frame K_IJ frame^T for a 3x3 block of the local stiffness, which beam_local_stiffness
/// builds as diag(alpha, beta, beta) plus gamma (E_yz - E_zy): with the frame's columns
/// e1, e2, e3 orthonormal that is beta I + (alpha - beta) e1 e1^T + gamma (e2 e3^T - e3 e2^T).
Eigen::Matrix3d rotated_block(const Matrix12d& k, int row, int col, const FrameProducts& products) {
  const double alpha = k(row, col), beta = k(row + 1, col + 1), gamma = k(row + 1, col + 2);
  Eigen::Matrix3d block = (alpha - beta) * products.axial;
  if (gamma != 0.0) block.noalias() += gamma * products.twist;
  for (int d = 0; d < 3; ++d) block(d, d) += beta;
  return block;
}

/// Fills a symmetric 6x6 tangent block from its upper 3x3 blocks (the lower-left mirrors the upper-right).
void set_symmetric_6x6(Matrix6d& block, const Eigen::Matrix3d& top_left, const Eigen::Matrix3d& top_right,
                       const Eigen::Matrix3d& bottom_right) {
  block.topLeftCorner<3, 3>() = top_left;
  block.topRightCorner<3, 3>() = top_right;
  block.bottomLeftCorner<3, 3>() = top_right.transpose();
  block.bottomRightCorner<3, 3>() = bottom_right;
}

}  // namespace

BeamResponse corotational_beam_response(const BeamStiffness& stiffness, double rest_length_m,
                                        const BeamEnds& ends) noexcept {
  const Eigen::Vector3d chord = ends.position_b_m - ends.position_a_m;
  const double length_m = chord.norm();
  const Eigen::Vector3d e1 = chord / length_m;
  // Mean node frame, half way from a to b along the shorter arc: the normalized sum of the
  // two unit quaternions taken in one hemisphere (a slerp at one half).
  const double hemisphere = ends.rotation_a.dot(ends.rotation_b) < 0.0 ? -1.0 : 1.0;
  const Eigen::Quaterniond mean(
      Eigen::Vector4d(ends.rotation_a.coeffs() + hemisphere * ends.rotation_b.coeffs()).normalized());
  const Eigen::Vector3d y_mean = mean * Eigen::Vector3d::UnitY();
  const Eigen::Vector3d e3 = e1.cross(y_mean).normalized();
  const Eigen::Vector3d e2 = e3.cross(e1);
  Eigen::Matrix3d frame;
  frame.col(0) = e1;
  frame.col(1) = e2;
  frame.col(2) = e3;
  const Eigen::Quaterniond element(frame);

  Vector12d local = Vector12d::Zero();
  local(6) = length_m - rest_length_m;
  local.segment<3>(3) = rotation_vector_from_quaternion(element.conjugate() * ends.rotation_a);
  local.segment<3>(9) = rotation_vector_from_quaternion(element.conjugate() * ends.rotation_b);
  // K local over the nonzero terms on the moved freedoms, each sum in freedom order from zero.
  Vector12d local_forces;
  for (std::size_t i = 0; i < 12; ++i) {
    double sum = 0.0;
    for (int t = 0; t < stiffness.force_term_count[i]; ++t) {
      const BeamStiffness::Term& term = stiffness.force_terms[i][static_cast<std::size_t>(t)];
      sum += term.value * local(term.freedom);
    }
    local_forces(static_cast<Eigen::Index>(i)) = sum;
  }

  BeamResponse response;
  for (int block = 0; block < 4; ++block)
    response.forces.segment<3>(3 * block).noalias() = frame * local_forces.segment<3>(3 * block);
  const FrameProducts products = frame_products(frame);
  std::array<Eigen::Matrix3d, BeamStiffness::kTangentBlocks> blocks;
  for (std::size_t b = 0; b < blocks.size(); ++b) {
    const auto same = static_cast<std::size_t>(stiffness.same_block_as[b]);
    blocks[b] =
        same < b ? blocks[same] : rotated_block(stiffness.local, kTangentBlocks[b][0], kTangentBlocks[b][1], products);
  }
  set_symmetric_6x6(response.tangent_aa, blocks[0], blocks[1], blocks[2]);
  response.tangent_ab << blocks[3], blocks[4], blocks[5], blocks[6];
  set_symmetric_6x6(response.tangent_bb, blocks[7], blocks[8], blocks[9]);
  return response;
}

}  // namespace nav
