// The kinematics and forces of the frame-based tissue (digest 002, section 6 items 1-7):
// partition of unity, zero force at rest and under rigid motions of all frames, forces that
// are the gradient of the energy, Hooke's constants of the corrected Appendix B, and the
// tangent against finite differences (exact at rest; away from rest the size of what the
// paper's material tangent leaves out, with and without the geometric stiffness).
#include <gtest/gtest.h>

#include <cstdio>
#include <random>

#include "connective/connective_test_support.hpp"

namespace nav {
namespace {

using testing::block_grid;
using testing::move_dof;
using testing::scene_of;
using testing::turn_frame;

constexpr ElasticMaterial kMaterial{1.0e4, 0.3, 1000.0};

struct Block {
  FrameTissueModel model;
  FrameTissueData data;
};

Block make_block(bool geometric) {
  FrameGrid grid = block_grid({3, 3, 2}, {0.01, 0.012, 0.02});
  FrameTissueOptions options;
  options.geometric_stiffness = geometric;
  FrameTissueModel model =
      make_frame_tissue_model(scene_of(make_grid_layout(grid).value(), kMaterial), options).value();
  FrameTissueData data = make_frame_tissue_data(model).value();
  return {std::move(model), std::move(data)};
}

/// A fixed pseudo-random deformation: frames moved by up to 1 mm, turned by up to 0.2 rad.
void deform(FrameTissueData& data, double scale) {
  std::mt19937 random(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  for (std::size_t f = 0; f < data.positions_m.size() / 3; ++f) {
    for (int a = 0; a < 3; ++a) data.positions_m[3 * f + a] += scale * 1e-3 * unit(random);
    turn_frame(data, f, scale * 0.2 * Eigen::Vector3d(unit(random), unit(random), unit(random)));
  }
}

double max_abs(std::span<const double> values) {
  double m = 0.0;
  for (double v : values) m = std::max(m, std::abs(v));
  return m;
}

TEST(FrameKinematics, ShapeFunctionsArePartitionsOfUnity) {
  for (const FrameGrid& grid : {block_grid({4, 3, 3}, {0.01, 0.01, 0.02}), block_grid({4, 3, 1}, {0.01, 0.01, 0.0}),
                                block_grid({5, 1, 1}, {0.01, 0.0, 0.0})}) {
    FrameGrid sampled = grid;
    sampled.extent_m = {0.002, 0.002, 0.002};
    sampled.points_per_cell_axis = 3;
    const FrameLayout layout = make_grid_layout(sampled).value();
    for (std::size_t s = 0; s < layout.points_m.size(); ++s) {
      double sum = 0.0;
      Point3 gradient{};
      for (auto k = static_cast<std::size_t>(layout.neighbour_offsets[s]);
           k < static_cast<std::size_t>(layout.neighbour_offsets[s + 1]); ++k) {
        sum += layout.weights[k];
        for (int a = 0; a < 3; ++a) gradient[a] += layout.weight_gradients_per_m[k][a];
      }
      EXPECT_NEAR(sum, 1.0, 1e-12);
      for (double g : gradient) EXPECT_NEAR(g, 0.0, 1e-9);
    }
    double volume_m3 = 0.0;
    for (double v : layout.volumes_m3) volume_m3 += v;
    double expected_m3 = 1.0;
    for (int d = 0; d < 3; ++d)
      expected_m3 *= grid.counts[d] > 1 ? (grid.counts[d] - 1) * grid.spacing_m[d] : sampled.extent_m[d];
    EXPECT_NEAR(volume_m3, expected_m3, 1e-12 * expected_m3 + 1e-18);
  }
}

TEST(FrameKinematics, RigidMotionsOfAllFramesGiveZeroForce) {
  Block block = make_block(true);
  std::vector<double> forces(6 * static_cast<std::size_t>(block.model.frame_count()));
  elastic_forces(block.model, block.data, forces);
  EXPECT_LT(max_abs(forces), 1e-12);
  // The force scale of a 1 % strain, to compare the round-off with.
  const double scale_n = kMaterial.youngs_modulus_pa * 0.01 * 0.01 * 0.01;
  for (const Eigen::AngleAxisd& rotation : {Eigen::AngleAxisd(0.5 * M_PI, Eigen::Vector3d(1, 2, 3).normalized()),
                                            Eigen::AngleAxisd(M_PI, Eigen::Vector3d::UnitY())}) {
    FrameTissueData moved = make_frame_tissue_data(block.model).value();
    const Eigen::Vector3d shift(0.3, -1.0, 2.0);
    for (std::size_t f = 0; f < forces.size() / 6; ++f) {
      Eigen::Map<Eigen::Vector3d> x(moved.positions_m.data() + 3 * f);
      x = rotation * Eigen::Vector3d(x) + shift;
      turn_frame(moved, f, rotation.angle() * rotation.axis());
    }
    elastic_forces(block.model, moved, forces);
    EXPECT_LT(max_abs(forces), 1e-9 * scale_n);
    EXPECT_LT(elastic_energy_j(block.model, moved), 1e-20);
  }
}

TEST(FrameKinematics, ForcesAreMinusTheEnergyGradient) {
  Block block = make_block(true);
  deform(block.data, 1.0);
  const std::size_t dofs = 6 * static_cast<std::size_t>(block.model.frame_count());
  std::vector<double> forces(dofs);
  elastic_forces(block.model, block.data, forces);
  const double h = 1e-7, tolerance = 1e-6 * max_abs(forces);
  for (std::size_t k = 0; k < dofs; ++k) {
    move_dof(block.data, k, h);
    const double up = elastic_energy_j(block.model, block.data);
    move_dof(block.data, k, -2.0 * h);
    const double down = elastic_energy_j(block.model, block.data);
    move_dof(block.data, k, h);
    EXPECT_NEAR(forces[k], -(up - down) / (2.0 * h), tolerance) << "dof " << k;
  }
}

TEST(FrameKinematics, HookeConstantsAreTheCorrectedAppendixB) {
  // Energy of a small homogeneous strain eps H: W = V eps^2 / 2 H:C:H. Appendix B as printed
  // ((2 - nu) in the prefactor) would give C11 = E(1 - nu)/((1 + nu)(2 - nu)), 39 % less.
  Block block = make_block(true);
  const double e = kMaterial.youngs_modulus_pa, nu = kMaterial.poisson_ratio, eps = 1e-6;
  const double c11 = e * (1.0 - nu) / ((1.0 + nu) * (1.0 - 2.0 * nu)), c12 = e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu));
  const double mu = e / (2.0 * (1.0 + nu));
  double volume_m3 = 0.02 * 0.024 * 0.02;
  const auto energy_of = [&](const Eigen::Matrix3d& h) {
    FrameTissueData strained = make_frame_tissue_data(block.model).value();
    for (std::size_t f = 0; f < static_cast<std::size_t>(block.model.frame_count()); ++f) {
      Eigen::Map<Eigen::Vector3d> x(strained.positions_m.data() + 3 * f);
      x += eps * h * Eigen::Vector3d(x);
    }
    return elastic_energy_j(block.model, strained) / (0.5 * volume_m3 * eps * eps);
  };
  const Eigen::Matrix3d axial = Eigen::Vector3d::UnitX() * Eigen::Vector3d::UnitX().transpose();
  const Eigen::Matrix3d biaxial = axial + Eigen::Vector3d::UnitY() * Eigen::Vector3d::UnitY().transpose();
  const Eigen::Matrix3d shear = Eigen::Vector3d::UnitX() * Eigen::Vector3d::UnitY().transpose() +
                                Eigen::Vector3d::UnitY() * Eigen::Vector3d::UnitX().transpose();
  EXPECT_NEAR(energy_of(axial), c11, 1e-4 * c11);
  EXPECT_NEAR(energy_of(biaxial), 2.0 * c11 + 2.0 * c12, 1e-4 * c11);
  EXPECT_NEAR(energy_of(shear), 4.0 * mu, 1e-4 * c11);  // engineering shear 2 eps: C44 = mu
}

/// Relative norm of the difference between K and the finite-difference Jacobian of -f.
double tangent_error(Block& block) {
  const std::size_t dofs = 6 * static_cast<std::size_t>(block.model.frame_count());
  std::vector<double> forces(dofs), up(dofs), down(dofs), unit(dofs), product(dofs);
  double difference = 0.0, reference = 0.0;
  const double h = 1e-7;
  for (std::size_t k = 0; k < dofs; ++k) {
    move_dof(block.data, k, h);
    elastic_forces(block.model, block.data, up);
    move_dof(block.data, k, -2.0 * h);
    elastic_forces(block.model, block.data, down);
    move_dof(block.data, k, h);
    elastic_forces(block.model, block.data, forces);
    std::fill(unit.begin(), unit.end(), 0.0);
    unit[k] = 1.0;
    stiffness_product(block.model, block.data, unit, product);
    for (std::size_t i = 0; i < dofs; ++i) {
      const double fd = -(up[i] - down[i]) / (2.0 * h);
      difference += (product[i] - fd) * (product[i] - fd);
      reference += fd * fd;
    }
  }
  return std::sqrt(difference / reference);
}

TEST(FrameKinematics, TangentMatchesFiniteDifferencesAtRest) {
  for (bool geometric : {false, true}) {
    Block block = make_block(geometric);
    EXPECT_LT(tangent_error(block), 1e-7) << "geometric " << geometric;
  }
}

TEST(FrameKinematics, TangentAwayFromRestIsSymmetricAndReportsWhatItLeavesOut) {
  double errors[2];
  for (bool geometric : {false, true}) {
    Block block = make_block(geometric);
    deform(block.data, 1.0);
    // A 10 % stretch along x on top of the random deformation: the stress is tensile.
    for (std::size_t f = 0; f < static_cast<std::size_t>(block.model.frame_count()); ++f)
      block.data.positions_m[3 * f] *= 1.1;
    errors[geometric ? 1 : 0] = tangent_error(block);
    const std::size_t dofs = 6 * static_cast<std::size_t>(block.model.frame_count());
    std::vector<double> a(dofs), b(dofs), ka(dofs), kb(dofs), forces(dofs);
    std::mt19937 random(3);
    std::uniform_real_distribution<double> unit(-1.0, 1.0);
    for (std::size_t k = 0; k < dofs; ++k) a[k] = unit(random), b[k] = unit(random);
    elastic_forces(block.model, block.data, forces);
    stiffness_product(block.model, block.data, a, ka);
    stiffness_product(block.model, block.data, b, kb);
    double bka = 0.0, akb = 0.0, norm = 0.0;
    for (std::size_t k = 0; k < dofs; ++k) bka += b[k] * ka[k], akb += a[k] * kb[k], norm += std::abs(b[k] * ka[k]);
    EXPECT_NEAR(bka, akb, 1e-12 * norm);
    double aka = 0.0;
    for (std::size_t k = 0; k < dofs; ++k) aka += a[k] * ka[k];
    EXPECT_GT(aka, 0.0);
  }
  std::printf(
      "relative tangent error under a 10 %% stretch and 0.2 rad turns: material only %.3f, with geometric %.3f\n",
      errors[0], errors[1]);
  EXPECT_LT(errors[1], errors[0]);
  EXPECT_LT(errors[1], 0.5);
}

}  // namespace
}  // namespace nav
