#include "nav/tissue/tet_fem_kernels.hpp"

#include <algorithm>

#include "nav/tissue/st_venant_kirchhoff.hpp"
#include "nav/tissue/tet_kernels.hpp"

namespace nav::detail {
namespace {

using Gradients = Eigen::Map<const Eigen::Matrix<double, 4, 3, Eigen::RowMajor>>;
using Matrix34 = Eigen::Matrix<double, 3, 4>;

Matrix34 gather(const std::array<std::int32_t, 4>& tet, std::span<const double> v) {
  Matrix34 out;
  for (int a = 0; a < 4; ++a)
    for (int i = 0; i < 3; ++i) out(i, a) = v[3 * static_cast<std::size_t>(tet[a]) + i];
  return out;
}

void scatter_add(const std::array<std::int32_t, 4>& tet, const Matrix34& values, std::span<double> v) {
  for (int a = 0; a < 4; ++a)
    for (int i = 0; i < 3; ++i) v[3 * static_cast<std::size_t>(tet[a]) + i] += values(i, a);
}

Gradients gradients_of(const TetFemTables& tables, std::size_t e) {
  return Gradients(tables.gradients.data() + 12 * e);
}

/// Element e's 3x3 matrix (column-major) in a table of 9 per element.
Eigen::Map<const Eigen::Matrix3d> matrix_of(std::span<const double> matrices, std::size_t e) {
  return Eigen::Map<const Eigen::Matrix3d>(matrices.data() + 9 * e);
}

}  // namespace

int update_element_rotations(const TetFemTables& tables, std::span<const double> x,
                             std::span<double> rotations) noexcept {
  int inverted = 0;
  const bool corotational = tables.options.rotation == ElementRotation::corotational;
  const auto load = [&](std::size_t e, Eigen::Matrix3d& f) {
    f.noalias() = gather(tables.tets[e], x) * gradients_of(tables, e);
    if (f.determinant() > 0.0) return corotational;
    ++inverted;  // keeps its previous rotation
    return false;
  };
  const auto store = [&](std::size_t e, const Eigen::Matrix3d& rotation) {
    Eigen::Map<Eigen::Matrix3d>(rotations.data() + 9 * e) = rotation;
  };
  for_each_polar_rotation(tables.tets.size(), load, store);
  return inverted;
}

int count_inverted_elements(const TetFemTables& tables, std::span<const double> x) noexcept {
  int inverted = 0;
  for (std::size_t e = 0; e < tables.tets.size(); ++e)
    if (!((gather(tables.tets[e], x) * gradients_of(tables, e)).determinant() > 0.0)) ++inverted;
  return inverted;
}

void update_node_rotations(const TetFemTables& tables, std::span<const double> element_rotations,
                           std::span<double> node_rotations) noexcept {
  std::fill(node_rotations.begin(), node_rotations.end(), 0.0);
  for (std::size_t e = 0; e < tables.tets.size(); ++e)
    for (std::int32_t node : tables.tets[e])
      Eigen::Map<Eigen::Matrix3d>(node_rotations.data() + 9 * static_cast<std::size_t>(node)) +=
          matrix_of(element_rotations, e);
  const auto load = [&](std::size_t node, Eigen::Matrix3d& sum) {
    Eigen::Map<Eigen::Matrix3d> stored(node_rotations.data() + 9 * node);
    sum = stored;
    if (sum.determinant() > 0.0) return true;
    stored.setIdentity();  // the adjacent rotations cancelled out
    return false;
  };
  const auto store = [&](std::size_t node, const Eigen::Matrix3d& rotation) {
    Eigen::Map<Eigen::Matrix3d>(node_rotations.data() + 9 * node) = rotation;
  };
  for_each_polar_rotation(static_cast<std::size_t>(tables.node_count), load, store);
}

void add_elastic_forces(const TetFemTables& tables, std::span<const double> x, std::span<const double> rotations,
                        std::span<double> forces) noexcept {
  const bool stvk = tables.options.law == ElementLaw::st_venant_kirchhoff;
  const double gain_pa = tables.options.incompressibility_gain_pa;
  for (std::size_t e = 0; e < tables.tets.size(); ++e) {
    const auto g = gradients_of(tables, e);
    const Eigen::Matrix3d f = gather(tables.tets[e], x) * g;
    Eigen::Matrix3d stress;
    if (stvk) {
      stress = stvk_stress(f, tables.lame[e], gain_pa);
    } else {
      const auto r = matrix_of(rotations, e);
      Eigen::Matrix3d h = r.transpose() * f;
      h.diagonal().array() -= 1.0;
      stress = r * linear_stress(h, tables.lame[e]);
    }
    const Matrix34 element_forces = (-tables.volume_m3[e]) * stress * g.transpose();
    scatter_add(tables.tets[e], element_forces, forces);
  }
}

void update_tangent_stresses(const TetFemTables& tables, std::span<const double> x,
                             std::span<double> tangent_stresses) noexcept {
  if (tables.options.law != ElementLaw::st_venant_kirchhoff) return;
  for (std::size_t e = 0; e < tables.tets.size(); ++e)
    Eigen::Map<Eigen::Matrix3d>(tangent_stresses.data() + 9 * e) =
        stvk_tangent_stress(gather(tables.tets[e], x) * gradients_of(tables, e), tables.lame[e]);
}

void add_stiffness_product(const TetFemTables& tables, std::span<const double> x, std::span<const double> rotations,
                           std::span<const double> tangent_stresses, std::span<const double> p, double scale,
                           std::span<double> out) noexcept {
  const bool stvk = tables.options.law == ElementLaw::st_venant_kirchhoff;
  const double gain_pa = tables.options.incompressibility_gain_pa;
  for (std::size_t e = 0; e < tables.tets.size(); ++e) {
    const auto g = gradients_of(tables, e);
    const Eigen::Matrix3d df = gather(tables.tets[e], p) * g;
    Eigen::Matrix3d stress;
    if (stvk) {
      stress = stvk_stress_derivative(gather(tables.tets[e], x) * g, df, matrix_of(tangent_stresses, e), tables.lame[e],
                                      gain_pa);
    } else {
      const auto r = matrix_of(rotations, e);
      stress = r * linear_stress(r.transpose() * df, tables.lame[e]);
    }
    const Matrix34 element_product = (scale * tables.volume_m3[e]) * stress * g.transpose();
    scatter_add(tables.tets[e], element_product, out);
  }
}

double elastic_energy(const TetFemTables& tables, std::span<const double> x) noexcept {
  double energy_j = 0.0;
  const bool stvk = tables.options.law == ElementLaw::st_venant_kirchhoff;
  const bool corotational = tables.options.rotation == ElementRotation::corotational;
  for (std::size_t e = 0; e < tables.tets.size(); ++e) {
    const Eigen::Matrix3d f = gather(tables.tets[e], x) * gradients_of(tables, e);
    if (stvk) {
      energy_j +=
          tables.volume_m3[e] * stvk_energy_density(f, tables.lame[e], tables.options.incompressibility_gain_pa);
      continue;
    }
    Eigen::Matrix3d h = f;
    if (corotational && f.determinant() > 0.0) h = polar_rotation(f).transpose() * f;
    h.diagonal().array() -= 1.0;
    energy_j += tables.volume_m3[e] * linear_energy_density(h, tables.lame[e]);
  }
  return energy_j;
}

}  // namespace nav::detail
