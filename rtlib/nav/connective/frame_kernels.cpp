#include "nav/connective/frame_kernels.hpp"

#include <Eigen/Dense>
#include <algorithm>

namespace nav::detail {
namespace {

using Eigen::Matrix3d;
using Eigen::Vector3d;
using Matrix9 = Eigen::Matrix<double, 9, 9>;
using Matrix96 = Eigen::Matrix<double, 9, 6>;
using Matrix6 = Eigen::Matrix<double, 6, 6>;

Vector3d vec3(std::span<const double> v, std::size_t i) { return {v[3 * i], v[3 * i + 1], v[3 * i + 2]}; }
Matrix3d mat3(std::span<const double> v, std::size_t i) { return Eigen::Map<const Matrix3d>(v.data() + 9 * i); }

/// Green-Lagrange strain and the St Venant-Kirchhoff second Piola-Kirchhoff stress (eq. 18).
Matrix3d second_piola(const Matrix3d& f, const LameParameters& lame) {
  Matrix3d e = 0.5 * (f.transpose() * f);
  e.diagonal().array() -= 0.5;
  Matrix3d s = (2.0 * lame.mu_pa) * e;
  s.diagonal().array() += lame.lambda_pa * e.trace();
  return s;
}

/// The positive part of a symmetric matrix (identity work when already positive definite).
Matrix3d positive_part(const Matrix3d& s) {
  if (s(0, 0) > 0.0 && s(0, 0) * s(1, 1) - s(0, 1) * s(1, 0) > 0.0 && s.determinant() > 0.0) return s;
  Eigen::SelfAdjointEigenSolver<Matrix3d> eigen;
  eigen.computeDirect(s);
  return eigen.eigenvectors() * eigen.eigenvalues().cwiseMax(0.0).asDiagonal() * eigen.eigenvectors().transpose();
}

/// dP = dF Sg + F C:sym(F^T dF): the tangent of P = F S, with the material part of the paper
/// (eqs. 22-23) and the geometric stress Sg (zero for the paper's tangent).
Matrix3d stress_derivative(const Matrix3d& f, const Matrix3d& sg, const Matrix3d& df, const LameParameters& lame) {
  const Matrix3d ft_df = f.transpose() * df;
  const Matrix3d de = 0.5 * (ft_df + ft_df.transpose());
  Matrix3d ds = (2.0 * lame.mu_pa) * de;
  ds.diagonal().array() += lame.lambda_pa * de.trace();
  return df * sg + f * ds;
}

/// J^T vec(P) for one pair (eqs. 10, 17 without the volume): the force dW/dx = P g and the
/// torque a x (P g) + w sum_c R_c x P_c on the frame.
void scatter(const Matrix3d& p, const Vector3d& g, const Vector3d& arm, double w, const Matrix3d& r, double scale,
             double* out) {
  const Vector3d pg = p * g;
  Vector3d torque = arm.cross(pg);
  for (int c = 0; c < 3; ++c) torque += w * r.col(c).cross(p.col(c));
  for (int a = 0; a < 3; ++a) {
    out[a] += scale * pg[a];
    out[3 + a] += scale * torque[a];
  }
}

/// Adds volume times P : d2F/dr2 for one pair, symmetrised: with b = P g,
/// sym(b a^T) - (a.b) I + w (sym(P R^T) - tr(P^T R) I). F is linear in each frame's position and
/// rotation matrix, so only the second derivative in the exponential coordinates of the
/// frame's own rotation is left (the part of the tangent the paper neglects with the geometric
/// stiffness; without it, rotation fields that strain no point at first order are free).
void add_spin_stiffness(const Matrix3d& p, const Vector3d& g, const Vector3d& arm, double w, const Matrix3d& r,
                        double volume, double* out) {
  const Vector3d b = p * g;
  const Matrix3d ba = b * arm.transpose(), pr = p * r.transpose();
  Matrix3d h = 0.5 * (ba + ba.transpose()) + (0.5 * w) * (pr + pr.transpose());
  h.diagonal().array() -= arm.dot(b) + w * pr.trace();
  Eigen::Map<Matrix3d>(out) += volume * h;
}

/// The pair's Jacobian of vec(F) (column-major) with respect to (dx, dr) of its frame.
Matrix96 pair_jacobian(const Vector3d& g, const Vector3d& arm, double w, const Matrix3d& r) {
  Matrix96 j = Matrix96::Zero();
  for (int a = 0; a < 3; ++a)
    for (int c = 0; c < 3; ++c) j(3 * c + a, a) = g[c];
  for (int b = 0; b < 3; ++b) {
    const Vector3d e = Vector3d::Unit(b);
    const Matrix3d df = e.cross(arm) * g.transpose();
    for (int c = 0; c < 3; ++c) {
      const Vector3d column = df.col(c) + w * e.cross(r.col(c));
      for (int a = 0; a < 3; ++a) j(3 * c + a, 3 + b) = column[a];
    }
  }
  return j;
}

/// Deformation gradient of point s (eq. 8 with rest orientations I), writing its pairs' arms.
Matrix3d point_gradient(const FrameTables& t, std::span<const double> x, std::span<const double> rotations,
                        std::size_t s, std::span<double> arms) {
  Matrix3d f = Matrix3d::Zero();
  for (auto k = static_cast<std::size_t>(t.offsets[s]); k < static_cast<std::size_t>(t.offsets[s + 1]); ++k) {
    const auto i = static_cast<std::size_t>(t.pair_frame[k]);
    const Matrix3d r = mat3(rotations, i);
    const Vector3d arm = r * vec3(t.pair_rest_arm, k);
    for (int a = 0; a < 3; ++a) arms[3 * k + a] = arm[a];
    f.noalias() += (vec3(x, i) + arm) * vec3(t.pair_gradient, k).transpose();
    f.noalias() += t.pair_weight[k] * r;
  }
  return f;
}

}  // namespace

void update_rotations(const FrameTables& tables, std::span<const double> orientations, std::span<double> rotations,
                      std::span<double> inertias) noexcept {
  for (std::size_t i = 0; i < static_cast<std::size_t>(tables.frame_count); ++i) {
    const Eigen::Quaterniond q(orientations[4 * i], orientations[4 * i + 1], orientations[4 * i + 2],
                               orientations[4 * i + 3]);
    const Matrix3d r = q.toRotationMatrix();
    Eigen::Map<Matrix3d>(rotations.data() + 9 * i) = r;
    Eigen::Map<Matrix3d>(inertias.data() + 9 * i) = r * mat3(tables.rest_inertia_kg_m2, i) * r.transpose();
  }
}

int add_elastic_forces(const FrameTables& t, const FrameWorkspace& work, std::span<double> forces) noexcept {
  int inverted = 0;
  const bool geometric = t.options.geometric_stiffness;
  std::fill(work.frame_spins.begin(), work.frame_spins.end(), 0.0);
  for (std::size_t s = 0; s < static_cast<std::size_t>(t.point_count); ++s) {
    const Matrix3d f = point_gradient(t, work.positions_m, work.rotations, s, work.pair_arms);
    if (!(f.determinant() > 0.0)) ++inverted;
    const Matrix3d stress = second_piola(f, t.lame);
    const Matrix3d p = f * stress;
    Eigen::Map<Matrix3d>(work.point_gradients.data() + 9 * s) = f;
    Eigen::Map<Matrix3d>(work.point_stresses.data() + 9 * s) = geometric ? positive_part(stress) : Matrix3d::Zero();
    for (auto k = static_cast<std::size_t>(t.offsets[s]); k < static_cast<std::size_t>(t.offsets[s + 1]); ++k) {
      const auto i = static_cast<std::size_t>(t.pair_frame[k]);
      scatter(p, vec3(t.pair_gradient, k), vec3(work.pair_arms, k), t.pair_weight[k], mat3(work.rotations, i),
              -t.volume_m3[s], forces.data() + 6 * i);
      if (geometric)
        add_spin_stiffness(p, vec3(t.pair_gradient, k), vec3(work.pair_arms, k), t.pair_weight[k],
                           mat3(work.rotations, i), t.volume_m3[s], work.frame_spins.data() + 9 * i);
    }
  }
  if (geometric)
    for (std::size_t i = 0; i < static_cast<std::size_t>(t.frame_count); ++i) {
      Eigen::Map<Matrix3d> spin(work.frame_spins.data() + 9 * i);
      spin = positive_part(spin);
    }
  return inverted;
}

void add_gravity(const FrameTables& t, const FrameWorkspace& work, double load_scale,
                 std::span<double> forces) noexcept {
  const Vector3d g(t.gravity_m_s2[0], t.gravity_m_s2[1], t.gravity_m_s2[2]);
  for (std::size_t s = 0; s < static_cast<std::size_t>(t.point_count); ++s) {
    const double mass_kg = load_scale * t.density_kg_m3 * t.volume_m3[s];
    for (auto k = static_cast<std::size_t>(t.offsets[s]); k < static_cast<std::size_t>(t.offsets[s + 1]); ++k) {
      const auto i = static_cast<std::size_t>(t.pair_frame[k]);
      const Vector3d weight = (t.pair_weight[k] * mass_kg) * g;
      const Vector3d torque = vec3(work.pair_arms, k).cross(weight);
      for (int a = 0; a < 3; ++a) {
        forces[6 * i + a] += weight[a];
        forces[6 * i + 3 + a] += torque[a];
      }
    }
  }
}

void add_stiffness_product(const FrameTables& t, const FrameWorkspace& work, std::span<const double> p, double scale,
                           std::span<double> out) noexcept {
  for (std::size_t s = 0; s < static_cast<std::size_t>(t.point_count); ++s) {
    const Matrix3d f = mat3(work.point_gradients, s);
    Matrix3d df = Matrix3d::Zero();
    for (auto k = static_cast<std::size_t>(t.offsets[s]); k < static_cast<std::size_t>(t.offsets[s + 1]); ++k) {
      const auto i = static_cast<std::size_t>(t.pair_frame[k]);
      const Vector3d dx = vec3(p, 2 * i), dr = vec3(p, 2 * i + 1);
      const Matrix3d r = mat3(work.rotations, i);
      df.noalias() += (dx + dr.cross(vec3(work.pair_arms, k))) * vec3(t.pair_gradient, k).transpose();
      for (int c = 0; c < 3; ++c) df.col(c) += t.pair_weight[k] * dr.cross(r.col(c));
    }
    const Matrix3d dp = stress_derivative(f, mat3(work.point_stresses, s), df, t.lame);
    for (auto k = static_cast<std::size_t>(t.offsets[s]); k < static_cast<std::size_t>(t.offsets[s + 1]); ++k) {
      const auto i = static_cast<std::size_t>(t.pair_frame[k]);
      scatter(dp, vec3(t.pair_gradient, k), vec3(work.pair_arms, k), t.pair_weight[k], mat3(work.rotations, i),
              scale * t.volume_m3[s], out.data() + 6 * i);
    }
  }
  if (!t.options.geometric_stiffness) return;
  for (std::size_t i = 0; i < static_cast<std::size_t>(t.frame_count); ++i) {
    const Vector3d spin = mat3(work.frame_spins, i) * vec3(p, 2 * i + 1);
    for (int a = 0; a < 3; ++a) out[6 * i + 3 + a] += scale * spin[a];
  }
}

void add_mass_product(const FrameTables& t, std::span<const double> inertias, std::span<const double> p, double scale,
                      std::span<double> out) noexcept {
  for (std::size_t i = 0; i < static_cast<std::size_t>(t.frame_count); ++i) {
    const Vector3d spin = mat3(inertias, i) * vec3(p, 2 * i + 1);
    for (int a = 0; a < 3; ++a) {
      out[6 * i + a] += scale * t.mass_kg[i] * p[6 * i + a];
      out[6 * i + 3 + a] += scale * spin[a];
    }
  }
}

void assemble(const FrameTables& t, const FrameWorkspace& work, std::span<const double> inertias, double mass_scale,
              double stiffness_scale, std::span<double> blocks, std::span<double> band) noexcept {
  std::fill(blocks.begin(), blocks.end(), 0.0);
  std::fill(band.begin(), band.end(), 0.0);
  const auto b = static_cast<std::size_t>(t.half_bandwidth);
  const auto add = [&](std::size_t fi, std::size_t fj, const Matrix6& m) {
    if (fi == fj) Eigen::Map<Matrix6>(blocks.data() + 36 * fi) += m;
    if (band.empty()) return;
    for (int c = 0; c < 6; ++c)
      for (int r = 0; r < 6; ++r) {
        const std::size_t row = 6 * fi + static_cast<std::size_t>(r), column = 6 * fj + static_cast<std::size_t>(c);
        if (row >= column) band[column * (b + 1) + (row - column)] += m(r, c);
      }
  };
  for (std::size_t i = 0; i < static_cast<std::size_t>(t.frame_count); ++i) {
    Matrix6 m = Matrix6::Zero();
    m.diagonal().head<3>().setConstant(mass_scale * t.mass_kg[i]);
    m.bottomRightCorner<3, 3>() = mass_scale * mat3(inertias, i) + stiffness_scale * mat3(work.frame_spins, i);
    add(i, i, m);
  }
  std::array<Matrix96, 8> jacobians;
  std::array<Matrix96, 8> stressed;
  for (std::size_t s = 0; s < static_cast<std::size_t>(t.point_count); ++s) {
    const Matrix3d f = mat3(work.point_gradients, s), sg = mat3(work.point_stresses, s);
    Matrix9 d;
    for (int m = 0; m < 9; ++m) {
      Matrix3d df = Matrix3d::Zero();
      df(m % 3, m / 3) = 1.0;
      d.col(m) = Eigen::Map<const Eigen::Matrix<double, 9, 1>>(stress_derivative(f, sg, df, t.lame).data());
    }
    const auto first = static_cast<std::size_t>(t.offsets[s]), last = static_cast<std::size_t>(t.offsets[s + 1]);
    // Points have at most 8 neighbours on grids; larger neighbourhoods go by chunks of 8.
    for (std::size_t a0 = first; a0 < last; a0 += 8)
      for (std::size_t b0 = first; b0 < last; b0 += 8) {
        const std::size_t na = std::min<std::size_t>(8, last - a0), nb = std::min<std::size_t>(8, last - b0);
        for (std::size_t k = 0; k < nb; ++k) {
          const std::size_t pair = b0 + k;
          jacobians[k] = pair_jacobian(vec3(t.pair_gradient, pair), vec3(work.pair_arms, pair), t.pair_weight[pair],
                                       mat3(work.rotations, static_cast<std::size_t>(t.pair_frame[pair])));
          stressed[k] = d * jacobians[k];
        }
        for (std::size_t ka = 0; ka < na; ++ka) {
          const std::size_t pa = a0 + ka;
          const Matrix96 ja = pair_jacobian(vec3(t.pair_gradient, pa), vec3(work.pair_arms, pa), t.pair_weight[pa],
                                            mat3(work.rotations, static_cast<std::size_t>(t.pair_frame[pa])));
          for (std::size_t kb = 0; kb < nb; ++kb) {
            const auto fi = static_cast<std::size_t>(t.pair_frame[pa]),
                       fj = static_cast<std::size_t>(t.pair_frame[b0 + kb]);
            if (fi < fj) continue;
            const Matrix6 m = (stiffness_scale * t.volume_m3[s]) * (ja.transpose() * stressed[kb]);
            add(fi, fj, m);
          }
        }
      }
  }
}

double elastic_energy(const FrameTables& t, std::span<const double> positions_m,
                      std::span<const double> orientations) noexcept {
  double energy_j = 0.0;
  for (std::size_t s = 0; s < static_cast<std::size_t>(t.point_count); ++s) {
    Matrix3d f = Matrix3d::Zero();
    for (auto k = static_cast<std::size_t>(t.offsets[s]); k < static_cast<std::size_t>(t.offsets[s + 1]); ++k) {
      const auto i = static_cast<std::size_t>(t.pair_frame[k]);
      const Matrix3d r = Eigen::Quaterniond(orientations[4 * i], orientations[4 * i + 1], orientations[4 * i + 2],
                                            orientations[4 * i + 3])
                             .toRotationMatrix();
      f.noalias() += (vec3(positions_m, i) + r * vec3(t.pair_rest_arm, k)) * vec3(t.pair_gradient, k).transpose();
      f.noalias() += t.pair_weight[k] * r;
    }
    Matrix3d e = 0.5 * (f.transpose() * f);
    e.diagonal().array() -= 0.5;
    energy_j += t.volume_m3[s] * (0.5 * t.lame.lambda_pa * e.trace() * e.trace() + t.lame.mu_pa * e.squaredNorm());
  }
  return energy_j;
}

}  // namespace nav::detail
