#include "nav/reduced/reduced_forces.hpp"

#include <algorithm>

#include "nav/reduced/dense_cholesky.hpp"
#include "nav/reduced/stvk_polynomial.hpp"
#include "nav/tissue/st_venant_kirchhoff.hpp"
#include "nav/tissue/tet_kernels.hpp"

namespace nav::detail {
namespace {

using Map3 = Eigen::Map<Eigen::Matrix3d>;
using ConstMap3 = Eigen::Map<const Eigen::Matrix3d>;

/// The 12 sample vertex values of (rows x q) + (lift x d), vertex-major.
void gather(const ReducedTables& t, int s, const ReducedState& state, double* u12) noexcept {
  const int r = t.r;
  const double* rows = t.sample_rows.data() + static_cast<std::size_t>(12 * r) * static_cast<std::size_t>(s);
  for (int i = 0; i < 12; ++i) u12[i] = dot(rows + i * r, state.q.data(), r);
  if (!t.has_lift) return;
  const double* lift = t.sample_lift.data() + 36 * static_cast<std::size_t>(s);
  for (int i = 0; i < 12; ++i)
    u12[i] += lift[3 * i] * state.prescribed_m[0] + lift[3 * i + 1] * state.prescribed_m[1] + lift[3 * i + 2] * state.prescribed_m[2];
}

/// force += U_s^T f12.
void scatter(const ReducedTables& t, int s, const double* f12, std::span<double> force) noexcept {
  const int r = t.r;
  const double* rows = t.sample_rows.data() + static_cast<std::size_t>(12 * r) * static_cast<std::size_t>(s);
  for (int i = 0; i < 12; ++i) {
    const double value = f12[i];
    for (int j = 0; j < r; ++j) force[static_cast<std::size_t>(j)] += rows[i * r + j] * value;
  }
}

/// f12 += w K_e u12 = G^T G u12 (G = sqrt(w V) D^1/2 B): the sample's linear force taken back
/// out, as the cubature approximates the non-linear remainder f + K u only.
void add_rest_stiffness_force(const ReducedTables& t, int s, const double* u12, double* f12) noexcept {
  const double* g = t.sample_root_stiffness.data() + 72 * static_cast<std::size_t>(s);
  double strain[6];
  for (int i = 0; i < 6; ++i) strain[i] = dot(g + 12 * i, u12, 12);
  for (int k = 0; k < 12; ++k) {
    double value = 0.0;
    for (int i = 0; i < 6; ++i) value += g[12 * i + k] * strain[i];
    f12[k] += value;
  }
}

}  // namespace

void sample_deformation(const ReducedTables& t, int s, const ReducedState& state, double* u12, double* f9) noexcept {
  gather(t, s, state, u12);
  const double* g = t.sample_gradients.data() + 12 * static_cast<std::size_t>(s);
  Map3 f(f9);
  f.setIdentity();  // F = I + sum_a u_a g_a^T, as sum_a g_a = 0
  for (int a = 0; a < 4; ++a)
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i) f(i, j) += u12[3 * a + i] * g[3 * a + j];
}

void add_corotational_force(const ReducedTables& t, int s, const double* u12, const double* rotation, std::span<double> force) noexcept {
  const ConstMap3 rot(rotation);
  const double* rest = t.sample_rest_m.data() + 12 * static_cast<std::size_t>(s);
  const double* g = t.sample_root_stiffness.data() + 72 * static_cast<std::size_t>(s);
  double local[12];
  for (int a = 0; a < 4; ++a) {  // R^T x_a - X_a
    const Eigen::Vector3d x(rest[3 * a] + u12[3 * a], rest[3 * a + 1] + u12[3 * a + 1], rest[3 * a + 2] + u12[3 * a + 2]);
    const Eigen::Vector3d back = rot.transpose() * x;
    for (int c = 0; c < 3; ++c) local[3 * a + c] = back[c] - rest[3 * a + c];
  }
  double strain[6];
  for (int i = 0; i < 6; ++i) {
    double value = 0.0;
    for (int k = 0; k < 12; ++k) value += g[12 * i + k] * local[k];
    strain[i] = value;
  }
  double f12[12];
  for (int k = 0; k < 12; ++k) {
    double value = 0.0;
    for (int i = 0; i < 6; ++i) value += g[12 * i + k] * strain[i];
    local[k] = value;
  }
  for (int a = 0; a < 4; ++a) {  // -R G^T G (R^T x - X)
    const Eigen::Vector3d out = -(rot * Eigen::Vector3d(local[3 * a], local[3 * a + 1], local[3 * a + 2]));
    for (int c = 0; c < 3; ++c) f12[3 * a + c] = out[c];
  }
  add_rest_stiffness_force(t, s, u12, f12);
  scatter(t, s, f12, force);
}

void corotational_tangent_rows(const ReducedTables& t, int s, const double* rotation, std::span<double> rows_out) noexcept {
  const int r = t.r;
  const ConstMap3 rot(rotation);
  const double* rows = t.sample_rows.data() + static_cast<std::size_t>(12 * r) * static_cast<std::size_t>(s);
  const double* g = t.sample_root_stiffness.data() + 72 * static_cast<std::size_t>(s);
  // H = G blockdiag(R^T): H(i, 3a + k) = sum_c G(i, 3a + c) R(k, c); then V = H U_s.
  double h[72];
  for (int i = 0; i < 6; ++i)
    for (int a = 0; a < 4; ++a)
      for (int k = 0; k < 3; ++k)
        h[12 * i + 3 * a + k] = g[12 * i + 3 * a] * rot(k, 0) + g[12 * i + 3 * a + 1] * rot(k, 1) + g[12 * i + 3 * a + 2] * rot(k, 2);
  for (int i = 0; i < 6; ++i) {
    double* target = rows_out.data() + i * r;
    for (int j = 0; j < r; ++j) target[j] = h[12 * i] * rows[j];
    for (int m = 1; m < 12; ++m) {
      const double coefficient = h[12 * i + m];
      const double* source = rows + m * r;
      for (int j = 0; j < r; ++j) target[j] += coefficient * source[j];
    }
  }
}

void add_stvk_force(const ReducedTables& t, int s, const double* u12, const double* f9, std::span<double> force) noexcept {
  const Eigen::Matrix3d f = ConstMap3(f9);
  const Eigen::Matrix3d stress = stvk_stress(f, t.sample_lame[static_cast<std::size_t>(s)], t.gain_pa);
  const double* g = t.sample_gradients.data() + 12 * static_cast<std::size_t>(s);
  const double scale = -t.sample_weight_volume[static_cast<std::size_t>(s)];
  double f12[12];
  for (int a = 0; a < 4; ++a) {
    const Eigen::Vector3d out = scale * (stress * Eigen::Vector3d(g[3 * a], g[3 * a + 1], g[3 * a + 2]));
    for (int c = 0; c < 3; ++c) f12[3 * a + c] = out[c];
  }
  add_rest_stiffness_force(t, s, u12, f12);
  scatter(t, s, f12, force);
}

void add_stvk_tangent(const ReducedTables& t, int s, const double* f9, std::span<double> tangent) noexcept {
  const int r = t.r;
  const Eigen::Matrix3d f = ConstMap3(f9);
  const LameParameters& lame = t.sample_lame[static_cast<std::size_t>(s)];
  const Eigen::Matrix3d tangent_stress = stvk_tangent_stress(f, lame);
  const double* g = t.sample_gradients.data() + 12 * static_cast<std::size_t>(s);
  const double* rows = t.sample_rows.data() + static_cast<std::size_t>(12 * r) * static_cast<std::size_t>(s);
  const double weight_volume = t.sample_weight_volume[static_cast<std::size_t>(s)];
  for (int j = 0; j < r; ++j) {
    Eigen::Matrix3d df = Eigen::Matrix3d::Zero();
    for (int a = 0; a < 4; ++a)
      for (int c = 0; c < 3; ++c)
        for (int k = 0; k < 3; ++k) df(c, k) += rows[(3 * a + c) * r + j] * g[3 * a + k];
    const Eigen::Matrix3d dp = weight_volume * stvk_stress_derivative(f, df, tangent_stress, lame, t.gain_pa);
    double column[12];
    for (int a = 0; a < 4; ++a) {
      const Eigen::Vector3d out = dp * Eigen::Vector3d(g[3 * a], g[3 * a + 1], g[3 * a + 2]);
      for (int c = 0; c < 3; ++c) column[3 * a + c] = out[c];
    }
    for (int i = 0; i < 12; ++i)
      for (int k = 0; k < r; ++k) tangent[static_cast<std::size_t>(k * r + j)] += rows[i * r + k] * column[i];
  }
}

void linear_force(const ReducedTables& t, const ReducedState& state, std::span<double> force) noexcept {
  const int r = t.r;
  for (int i = 0; i < r; ++i) {
    double value = dot(t.stiffness_r.data() + i * r, state.q.data(), r);
    if (t.has_lift)
      for (int c = 0; c < 3; ++c) value += t.stiffness_lift_r[static_cast<std::size_t>(3 * i + c)] * state.prescribed_m[c];
    force[static_cast<std::size_t>(i)] = -value;
  }
}

int evaluate_internal_force(const ReducedTables& t, const ReducedState& state, ForceScratch scratch, std::span<double> force,
                            std::span<double> tangent) noexcept {
  const int r = t.r;
  const bool with_tangent = !tangent.empty();
  if (t.force_kind == ReducedForceKind::stvk_cubic_polynomial) {
    evaluate_stvk_polynomial(t, state.q, scratch.monomials, force, tangent);
    return 0;
  }
  if (t.force_kind == ReducedForceKind::linear) {
    linear_force(t, state, force);
    if (with_tangent) std::copy(t.stiffness_r.begin(), t.stiffness_r.end(), tangent.begin());
    return 0;
  }
  linear_force(t, state, force);  // exact linear part; the samples add the remainder
  if (with_tangent)
    for (std::size_t i = 0; i < tangent.size(); ++i) tangent[i] = t.stiffness_r[i] - t.sample_rest_tangent_r[i];
  const auto m = static_cast<std::size_t>(t.sample_count);
  int inverted = 0;
  double gradients[9];
  if (t.force_kind == ReducedForceKind::stvk_cubature) {
    for (std::size_t s = 0; s < m; ++s) {
      sample_deformation(t, static_cast<int>(s), state, scratch.displacements.data() + 12 * s, gradients);
      if (!(ConstMap3(gradients).determinant() > 0.0)) ++inverted;
      add_stvk_force(t, static_cast<int>(s), scratch.displacements.data() + 12 * s, gradients, force);
      if (with_tangent) add_stvk_tangent(t, static_cast<int>(s), gradients, tangent);
    }
    return inverted;
  }
  for_each_polar_rotation(
      m,
      [&](std::size_t s, Eigen::Matrix3d& f) {
        sample_deformation(t, static_cast<int>(s), state, scratch.displacements.data() + 12 * s, gradients);
        f = ConstMap3(gradients);
        const bool usable = f.determinant() > 0.0;
        if (!usable) ++inverted;
        return usable;
      },
      [&](std::size_t s, const Eigen::Matrix3d& rotation) { Map3(scratch.rotations.data() + 9 * s) = rotation; });
  for (std::size_t s = 0; s < m; ++s) {
    add_corotational_force(t, static_cast<int>(s), scratch.displacements.data() + 12 * s, scratch.rotations.data() + 9 * s, force);
    if (!with_tangent) continue;
    // tangent += V^T V with V the sample's 6 x r rows: one pass over the r x r tangent per
    // sample (a rank-6 update in a fixed order), whole rows for regular vector loops.
    const std::span<double> v = scratch.tangent_rows.first(6 * static_cast<std::size_t>(r));
    corotational_tangent_rows(t, static_cast<int>(s), scratch.rotations.data() + 9 * s, v);
    for (int i = 0; i < r; ++i) {
      const double v0 = v[static_cast<std::size_t>(i)], v1 = v[static_cast<std::size_t>(r + i)], v2 = v[static_cast<std::size_t>(2 * r + i)];
      const double v3 = v[static_cast<std::size_t>(3 * r + i)], v4 = v[static_cast<std::size_t>(4 * r + i)], v5 = v[static_cast<std::size_t>(5 * r + i)];
      const double* w = v.data();
      double* out = tangent.data() + i * r;
      for (int j = 0; j < r; ++j)
        out[j] += ((v0 * w[j] + v1 * w[r + j]) + (v2 * w[2 * r + j] + v3 * w[3 * r + j])) + (v4 * w[4 * r + j] + v5 * w[5 * r + j]);
    }
  }
  return inverted;
}

}  // namespace nav::detail
