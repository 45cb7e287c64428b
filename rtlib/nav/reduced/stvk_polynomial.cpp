#include "nav/reduced/stvk_polynomial.hpp"

#include <Eigen/Dense>
#include <algorithm>

#include "nav/reduced/dense_cholesky.hpp"

namespace nav::detail {
namespace {

std::size_t pairs(int r) { return static_cast<std::size_t>(r) * static_cast<std::size_t>(r + 1) / 2; }
std::size_t triples(int r) {
  return static_cast<std::size_t>(r) * static_cast<std::size_t>(r + 1) * static_cast<std::size_t>(r + 2) / 6;
}

/// Position of the pair {a, b} among the sorted pairs (x <= y) in lexicographic order.
Eigen::Index pair_index(int a, int b, int r) {
  const int x = std::min(a, b), y = std::max(a, b);
  return static_cast<Eigen::Index>(x) * r - static_cast<Eigen::Index>(x) * (x - 1) / 2 + (y - x);
}

/// Symmetric 3x3 matrices as 6-vectors (xx, yy, zz, xy, yz, zx) with the metric that makes
/// the plain dot product the double contraction: off-diagonal entries times sqrt(2).
using Voigt = Eigen::Matrix<double, 6, 1>;

Voigt voigt(const Eigen::Matrix3d& m) {
  const double s = std::sqrt(2.0);
  Voigt v;
  v << m(0, 0), m(1, 1), m(2, 2), s * m(0, 1), s * m(1, 2), s * m(2, 0);
  return v;
}

/// C(X) = lambda tr(X) I + 2 mu X in the same form.
Voigt elastic(const Voigt& x, const LameParameters& lame) {
  Voigt c = 2.0 * lame.mu_pa * x;
  const double trace = x[0] + x[1] + x[2];
  for (int k = 0; k < 3; ++k) c[k] += lame.lambda_pa * trace;
  return c;
}

}  // namespace

std::size_t stvk_polynomial_size(int r) {
  return static_cast<std::size_t>(r) * (static_cast<std::size_t>(r) + pairs(r) + triples(r));
}

std::vector<double> build_stvk_polynomial(const TetFemTables& tables, std::span<const double> rows, int r) {
  // Per element, with H_j = sum_a U_aj g_a^T, A_j = sym H_j and B_jk = sym(H_j^T H_k) / 2:
  // f_i = -V [C(E) : A_i + 2 sum_l q_l C(E) : B_li], E = sum q_j A_j + sum q_j q_k B_jk, so
  // K1_ij = V C(A_j):A_i, Q_ijk = V (C(B_jk):A_i + 2 C(A_k):B_ji), T_iljk = 2 V C(B_jk):B_li
  // over ordered indices, folded onto the sorted monomials at the end.
  const Eigen::Index rr = static_cast<Eigen::Index>(r) * r;
  Eigen::MatrixXd linear = Eigen::MatrixXd::Zero(r, r);
  Eigen::MatrixXd quadratic = Eigen::MatrixXd::Zero(r, rr);  // (i, j r + k)
  // B_jk = B_kj: the cubic products are kept over sorted pairs only, (pair(l, i), pair(j, k)).
  const auto p2 = static_cast<Eigen::Index>(pairs(r));
  Eigen::MatrixXd cubic = Eigen::MatrixXd::Zero(p2, p2);
  Eigen::MatrixXd b_sorted(6, p2), cb_sorted(6, p2);
  std::vector<Eigen::Matrix3d> h(static_cast<std::size_t>(r));
  Eigen::MatrixXd a(6, r), ca(6, r), b(6, rr), cb(6, rr);
  for (std::size_t e = 0; e < tables.tets.size(); ++e) {
    const LameParameters& lame = tables.lame[e];
    const double volume = tables.volume_m3[e];
    for (int j = 0; j < r; ++j) {
      Eigen::Matrix3d m = Eigen::Matrix3d::Zero();
      for (int v = 0; v < 4; ++v) {
        const Eigen::Vector3d g(tables.gradients.data() + 12 * e + 3 * v);
        const std::size_t row = 3 * static_cast<std::size_t>(tables.tets[e][v]);
        const Eigen::Vector3d u(rows[row * r + j], rows[(row + 1) * r + j], rows[(row + 2) * r + j]);
        m += u * g.transpose();
      }
      h[static_cast<std::size_t>(j)] = m;
      a.col(j) = voigt(0.5 * (m + m.transpose()));
      ca.col(j) = elastic(a.col(j), lame);
    }
    for (int j = 0; j < r; ++j)
      for (int k = 0; k < r; ++k) {
        const Eigen::Matrix3d p = h[static_cast<std::size_t>(j)].transpose() * h[static_cast<std::size_t>(k)];
        b.col(j * r + k) = voigt(0.25 * (p + p.transpose()));
        cb.col(j * r + k) = elastic(b.col(j * r + k), lame);
      }
    linear.noalias() += volume * a.transpose() * ca;     // (i, j): A_i . C(A_j)
    quadratic.noalias() += volume * a.transpose() * cb;  // (i, jk): A_i . C(B_jk)
    const Eigen::MatrixXd ca_b = ca.transpose() * b;     // (k, j i): C(A_k) . B_ji
    for (int i = 0; i < r; ++i)
      for (int j = 0; j < r; ++j)
        for (int k = 0; k < r; ++k) quadratic(i, j * r + k) += 2.0 * volume * ca_b(k, j * r + i);
    for (int j = 0, n = 0; j < r; ++j)
      for (int k = j; k < r; ++k, ++n) {
        b_sorted.col(n) = b.col(j * r + k);
        cb_sorted.col(n) = cb.col(j * r + k);
      }
    cubic.noalias() += (2.0 * volume) * b_sorted.transpose() * cb_sorted;  // (l i, j k): B_li . C(B_jk)
  }
  std::vector<double> coefficients;
  coefficients.reserve(stvk_polynomial_size(r));
  for (int i = 0; i < r; ++i)
    for (int j = 0; j < r; ++j) coefficients.push_back(linear(i, j));
  for (int i = 0; i < r; ++i)
    for (int j = 0; j < r; ++j)
      for (int k = j; k < r; ++k)
        coefficients.push_back(quadratic(i, j * r + k) + (j != k ? quadratic(i, k * r + j) : 0.0));
  for (int i = 0; i < r; ++i)
    for (int x = 0; x < r; ++x)
      for (int y = x; y < r; ++y)
        for (int z = y; z < r; ++z) {
          // Sum over the distinct orderings (l, j, k) of {x, y, z}.
          const int perms[6][3] = {{x, y, z}, {x, z, y}, {y, x, z}, {y, z, x}, {z, x, y}, {z, y, x}};
          double sum = 0.0;
          for (int p = 0; p < 6; ++p) {
            bool repeated = false;
            for (int q = 0; q < p; ++q)
              repeated =
                  repeated || (perms[q][0] == perms[p][0] && perms[q][1] == perms[p][1] && perms[q][2] == perms[p][2]);
            if (!repeated) sum += cubic(pair_index(perms[p][0], i, r), pair_index(perms[p][1], perms[p][2], r));
          }
          coefficients.push_back(sum);
        }
  return coefficients;
}

void evaluate_stvk_polynomial(const ReducedTables& t, std::span<const double> q, std::span<double> monomials,
                              std::span<double> force, std::span<double> tangent) noexcept {
  const int r = t.r;
  const std::size_t p2 = pairs(r), p3 = triples(r);
  double* m2 = monomials.data();
  double* m3 = monomials.data() + p2;
  std::size_t n2 = 0, n3 = 0;
  for (int x = 0; x < r; ++x)
    for (int y = x; y < r; ++y) {
      m2[n2++] = q[static_cast<std::size_t>(x)] * q[static_cast<std::size_t>(y)];
      for (int z = y; z < r; ++z)
        m3[n3++] = q[static_cast<std::size_t>(x)] * q[static_cast<std::size_t>(y)] * q[static_cast<std::size_t>(z)];
    }
  // m3 was filled in (x, y, z) order within each x, y: the same lexicographic order.
  const double* k1 = t.polynomial.data();
  const double* qc = k1 + static_cast<std::size_t>(r) * static_cast<std::size_t>(r);
  const double* tc = qc + static_cast<std::size_t>(r) * p2;
  for (int i = 0; i < r; ++i)
    force[static_cast<std::size_t>(i)] =
        -(dot(k1 + static_cast<std::size_t>(i) * static_cast<std::size_t>(r), q.data(), r) +
          dot(qc + static_cast<std::size_t>(i) * p2, m2, static_cast<int>(p2)) +
          dot(tc + static_cast<std::size_t>(i) * p3, m3, static_cast<int>(p3)));
  if (tangent.empty()) return;
  for (int i = 0; i < r * r; ++i) tangent[static_cast<std::size_t>(i)] = k1[i];
  for (int i = 0; i < r; ++i) {
    double* row = tangent.data() + i * r;
    const double* qi = qc + static_cast<std::size_t>(i) * p2;
    const double* ti = tc + static_cast<std::size_t>(i) * p3;
    std::size_t c2 = 0, c3 = 0;
    for (int x = 0; x < r; ++x)
      for (int y = x; y < r; ++y) {
        const double qx = q[static_cast<std::size_t>(x)], qy = q[static_cast<std::size_t>(y)];
        row[x] += qi[c2] * qy;
        row[y] += qi[c2] * qx;
        ++c2;
        for (int z = y; z < r; ++z) {
          const double qz = q[static_cast<std::size_t>(z)], coefficient = ti[c3++];
          row[x] += coefficient * qy * qz;
          row[y] += coefficient * qx * qz;
          row[z] += coefficient * qx * qy;
        }
      }
  }
  for (int i = 0; i < r; ++i)
    for (int j = 0; j < i; ++j) {
      const double mean =
          0.5 * (tangent[static_cast<std::size_t>(i * r + j)] + tangent[static_cast<std::size_t>(j * r + i)]);
      tangent[static_cast<std::size_t>(i * r + j)] = mean;
      tangent[static_cast<std::size_t>(j * r + i)] = mean;
    }
}

}  // namespace nav::detail
