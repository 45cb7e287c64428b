// The offline bases: Spectra's shift-invert Lanczos modes against a dense generalized eigen
// solver, a cantilever's first bending frequency against Euler-Bernoulli, M-orthonormality,
// the diaphragm lift, modal derivatives, and POD's exact reproduction of in-span snapshots.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <random>

#include "nav/mesh/geometry.hpp"
#include "nav/reduced/reduction.hpp"
#include "nav/tissue/tet_kernels.hpp"
#include "reduced/reduced_test_support.hpp"

namespace nav {
namespace {

using testing::basis_column;
using testing::basis_matrix;
using testing::BeamScene;
using testing::dof_masses;

TissueSolverOptions linear_options() {
  TissueSolverOptions options;
  options.rotation = ElementRotation::none;
  options.integrator = Integrator::quasi_static;
  return options;
}

/// K and M over the free dofs of `beam`, dense, and the free dofs' indices.
struct DenseSystem {
  Eigen::MatrixXd stiffness, mass;
  std::vector<Eigen::Index> free_dofs;
};

/// Dense K (element stiffnesses V B^T D B summed into a dense matrix) and lumped M over the
/// free dofs: an assembly independent of the reduction's sparse one.
DenseSystem dense_system(const BeamScene& beam) {
  const std::size_t n3 = 3 * beam.mesh.nodes_m.size();
  Eigen::MatrixXd stiffness = Eigen::MatrixXd::Zero(static_cast<Eigen::Index>(n3), static_cast<Eigen::Index>(n3));
  Eigen::VectorXd mass = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(n3));
  const LameParameters lame = lame_parameters(beam.scene.default_material);
  for (const auto& tet : beam.mesh.tets) {
    std::array<Point3, 4> corners;
    for (int a = 0; a < 4; ++a) corners[a] = beam.mesh.nodes_m[static_cast<std::size_t>(tet[a])];
    const double volume = signed_tet_volume_m3(corners[0], corners[1], corners[2], corners[3]);
    const Matrix12 ke = element_stiffness(shape_gradients(corners), lame, volume);
    for (int a = 0; a < 4; ++a) {
      mass.segment<3>(3 * tet[a]).array() += beam.scene.default_material.density_kg_m3 * volume / 4.0;
      for (int b = 0; b < 4; ++b) stiffness.block<3, 3>(3 * tet[a], 3 * tet[b]) += ke.block<3, 3>(3 * a, 3 * b);
    }
  }
  DenseSystem system;
  std::vector<bool> fixed(beam.mesh.nodes_m.size(), false);
  for (std::int32_t node : beam.scene.fixed_nodes) fixed[static_cast<std::size_t>(node)] = true;
  for (std::size_t i = 0; i < n3; ++i)
    if (!fixed[i / 3]) system.free_dofs.push_back(static_cast<Eigen::Index>(i));
  const auto n = static_cast<Eigen::Index>(system.free_dofs.size());
  system.stiffness.resize(n, n);
  system.mass = Eigen::MatrixXd::Zero(n, n);
  for (Eigen::Index i = 0; i < n; ++i) {
    system.mass(i, i) = mass[system.free_dofs[static_cast<std::size_t>(i)]];
    for (Eigen::Index j = 0; j < n; ++j)
      system.stiffness(i, j) =
          stiffness(system.free_dofs[static_cast<std::size_t>(i)], system.free_dofs[static_cast<std::size_t>(j)]);
  }
  return system;
}

TEST(ReducedBasis, LanczosModesMatchADenseGeneralizedEigenSolver) {
  const BeamScene beam({0.04, 0.01, 0.015}, 0.005);
  ReductionOptions options;
  options.source = ReducedBasisSource::linear_modes;
  options.basis_size = 6;
  const auto basis = make_modal_basis(beam.mesh, beam.scene, linear_options(), options);
  ASSERT_TRUE(basis.ok()) << basis.error().describe();
  const DenseSystem dense = dense_system(beam);
  Eigen::GeneralizedSelfAdjointEigenSolver<Eigen::MatrixXd> reference(dense.stiffness, dense.mass);
  ASSERT_EQ(reference.info(), Eigen::Success);
  // Eigenvalues to 1e-8 relative; each mode lies in the span of the dense modes of eigenvalues
  // within 1e-3 of its own (near-degenerate pairs may mix), to 1e-8.
  for (int j = 0; j < options.basis_size; ++j) {
    const double expected = reference.eigenvalues()[j];
    EXPECT_NEAR(basis.value().column_values[static_cast<std::size_t>(j)], expected, 1e-8 * expected) << j;
    Eigen::VectorXd mode(static_cast<Eigen::Index>(dense.free_dofs.size()));
    for (std::size_t k = 0; k < dense.free_dofs.size(); ++k)
      mode[static_cast<Eigen::Index>(k)] = basis_column(basis.value(), j)[dense.free_dofs[k]];
    double captured = 0.0;
    for (Eigen::Index k = 0; k < reference.eigenvalues().size(); ++k)
      if (std::abs(reference.eigenvalues()[k] - expected) < 1e-3 * expected)
        captured += std::pow(reference.eigenvectors().col(k).dot(dense.mass * mode), 2);
    EXPECT_NEAR(std::sqrt(captured), 1.0, 1e-8) << j;
  }
}

TEST(ReducedBasis, ModeEnergiesMatchTheFullOrderModel) {
  // An exact check through another code path: the full-order linear model's elastic energy of
  // a small multiple of an M-normalised mode phi is w^2 |a|^2 / 2.
  const BeamScene beam({0.04, 0.01, 0.015}, 0.005);
  ReductionOptions options;
  options.source = ReducedBasisSource::linear_modes;
  options.basis_size = 8;
  const auto basis = make_modal_basis(beam.mesh, beam.scene, linear_options(), options);
  ASSERT_TRUE(basis.ok()) << basis.error().describe();
  const TetFemModel model = make_tet_fem_model(beam.mesh, beam.scene, linear_options()).value();
  const Eigen::VectorXd mass = dof_masses(model);
  auto data = make_tet_fem_data(model).value();
  const auto rest = model.rest_positions_m();
  constexpr double kAmplitude = 1e-6;
  for (int j = 0; j < options.basis_size; ++j) {
    const double w2 = basis.value().column_values[static_cast<std::size_t>(j)];
    const Eigen::VectorXd phi = basis_column(basis.value(), j);
    for (std::size_t k = 0; k < rest.size(); ++k)
      data.positions_m[k] = rest[k] + kAmplitude * phi[static_cast<Eigen::Index>(k)];
    EXPECT_NEAR(elastic_energy_j(model, data) / (kAmplitude * kAmplitude), 0.5 * w2, 1e-8 * w2) << j;
    EXPECT_NEAR(phi.dot(mass.cwiseProduct(phi)), 1.0, 1e-10);
  }
}

TEST(ReducedBasis, ColumnsAreMassOrthonormalAndFixedRowsZero) {
  const BeamScene beam({0.06, 0.01, 0.01}, 0.005);
  ReductionOptions options;
  options.source = ReducedBasisSource::linear_modes;
  options.basis_size = 12;
  const auto basis = make_modal_basis(beam.mesh, beam.scene, linear_options(), options);
  ASSERT_TRUE(basis.ok()) << basis.error().describe();
  const TetFemModel model = make_tet_fem_model(beam.mesh, beam.scene, linear_options()).value();
  const Eigen::MatrixXd u = basis_matrix(basis.value());
  const Eigen::MatrixXd gram = u.transpose() * dof_masses(model).asDiagonal() * u;
  EXPECT_LT((gram - Eigen::MatrixXd::Identity(12, 12)).cwiseAbs().maxCoeff(), 1e-10);
  for (std::int32_t node : beam.scene.fixed_nodes) EXPECT_EQ(u.middleRows(3 * node, 3).cwiseAbs().maxCoeff(), 0.0);
  for (int j = 1; j < 12; ++j) EXPECT_LE(basis.value().column_values[j - 1], basis.value().column_values[j]);
  EXPECT_EQ(basis.value().mesh_fingerprint, mesh_fingerprint(beam.mesh));
  EXPECT_TRUE(basis.value().diaphragm_lift.empty());
}

TEST(ReducedBasis, CantileverFirstBendingFrequencyMatchesEulerBernoulli) {
  // A 10 cm beam of 1 x 1 cm, nu = 0 (no Poisson stiffening), 4 linear tetrahedra cubes
  // across: linear tetrahedra are stiff in bending (shear locking), by about 1/n^2 of the
  // elements across, plus the beam's finite slenderness (Timoshenko: about 1 %). The
  // frequencies of the two bending directions come out 7 % and 12 % above Euler-Bernoulli's
  // (the Kuhn lattice's tetrahedra are not symmetric between y and z); the test asserts both
  // are above by less than 15 %, and not below.
  constexpr double kLength = 0.1, kSide = 0.01;
  BeamScene beam({kLength, kSide, kSide}, 0.0025);
  beam.scene.default_material = {5.0e3, 0.0, 1000.0};
  ReductionOptions options;
  options.source = ReducedBasisSource::linear_modes;
  options.basis_size = 2;
  const auto basis = make_modal_basis(beam.mesh, beam.scene, linear_options(), options);
  ASSERT_TRUE(basis.ok()) << basis.error().describe();
  const double inertia = kSide * kSide * kSide * kSide / 12.0;
  const double euler_bernoulli =
      1.875104 * 1.875104 * std::sqrt(5.0e3 * inertia / (1000.0 * kSide * kSide * std::pow(kLength, 4)));
  const double measured = std::sqrt(basis.value().column_values[0]);
  std::printf("first bending: %.4f rad/s, Euler-Bernoulli %.4f rad/s (ratio %.4f)\n", measured, euler_bernoulli,
              measured / euler_bernoulli);
  EXPECT_GT(measured, 0.99 * euler_bernoulli);
  EXPECT_LT(measured, 1.12 * euler_bernoulli);
  const double second = std::sqrt(basis.value().column_values[1]);
  std::printf("second bending: %.4f rad/s (ratio %.4f)\n", second, second / euler_bernoulli);
  EXPECT_LT(measured, 1.15 * euler_bernoulli);
  EXPECT_LT(second, 1.15 * euler_bernoulli);
}

TEST(ReducedBasis, DiaphragmLiftIsTheStaticResponseToAUnitMove) {
  BeamScene beam({0.04, 0.01, 0.01}, 0.005);
  beam.scene.prescribed_nodes = testing::nodes_where(beam.mesh, 0, 0.04);
  ReductionOptions options;
  options.source = ReducedBasisSource::linear_modes;
  options.basis_size = 4;
  const auto basis = make_modal_basis(beam.mesh, beam.scene, linear_options(), options);
  ASSERT_TRUE(basis.ok()) << basis.error().describe();
  const auto& lift = basis.value().diaphragm_lift;
  ASSERT_EQ(lift.size(), 9 * beam.mesh.nodes_m.size());
  // The full-order linear quasi-static model moved by d reaches u = L d in one step.
  TissueScene weightless = beam.scene;
  weightless.gravity_m_s2 = {0.0, 0.0, 0.0};
  const TetFemModel still = make_tet_fem_model(beam.mesh, weightless, linear_options()).value();
  auto still_data = make_tet_fem_data(still).value();
  TissueInputs inputs;
  inputs.prescribed_displacement_m = {0.001, -0.002, 0.0005};
  step(still, still_data, inputs);
  const auto n3 = 3 * beam.mesh.nodes_m.size();
  double worst = 0.0, largest = 0.0;
  for (std::size_t i = 0; i < n3; ++i) {
    const double expected = still_data.positions_m[i] - still.rest_positions_m()[i];
    double lifted = 0.0;
    for (int c = 0; c < 3; ++c) lifted += lift[c * n3 + i] * inputs.prescribed_displacement_m[c];
    worst = std::max(worst, std::abs(lifted - expected));
    largest = std::max(largest, std::abs(expected));
  }
  EXPECT_LT(worst, 1e-9 * largest);
}

TEST(ReducedBasis, ModalDerivativesExtendTheModesMassOrthonormally) {
  const BeamScene beam({0.04, 0.01, 0.01}, 0.005);
  TissueSolverOptions stvk = linear_options();
  stvk.law = ElementLaw::st_venant_kirchhoff;
  ReductionOptions options;
  options.source = ReducedBasisSource::modal_derivatives;
  options.basis_size = 9;  // 3 modes and their 6 derivatives
  const auto basis = make_modal_basis(beam.mesh, beam.scene, stvk, options);
  ASSERT_TRUE(basis.ok()) << basis.error().describe();
  ReductionOptions modes_only = options;
  modes_only.source = ReducedBasisSource::linear_modes;
  modes_only.basis_size = 3;
  const auto modes = make_modal_basis(beam.mesh, beam.scene, stvk, modes_only).value();
  const TetFemModel model = make_tet_fem_model(beam.mesh, beam.scene, linear_options()).value();
  const Eigen::VectorXd mass = dof_masses(model);
  const Eigen::MatrixXd u = basis_matrix(basis.value());
  EXPECT_LT((u.transpose() * mass.asDiagonal() * u - Eigen::MatrixXd::Identity(9, 9)).cwiseAbs().maxCoeff(), 1e-9);
  for (int j = 0; j < 3; ++j) {  // the first columns are the modes themselves
    EXPECT_NEAR(std::abs(basis_column(basis.value(), j).dot(mass.cwiseProduct(basis_column(modes, j)))), 1.0, 1e-8);
    EXPECT_NEAR(basis.value().column_values[j], modes.column_values[j], 1e-8 * modes.column_values[j]);
  }
  // The derivatives of bending modes are mostly axial stretching: the modes have almost no x
  // motion, the derivative columns carry a large share of theirs.
  auto axial_share = [&](int j) {
    double axial = 0.0, total = 0.0;
    for (Eigen::Index i = 0; i < u.rows(); ++i) {
      total += mass[i] * u(i, j) * u(i, j);
      if (i % 3 == 0) axial += mass[i] * u(i, j) * u(i, j);
    }
    return axial / total;
  };
  EXPECT_LT(axial_share(0), 0.05);
  EXPECT_GT(axial_share(3), 0.3);
}

TEST(ReducedBasis, PodReproducesSnapshotsInItsSpan) {
  const BeamScene beam({0.04, 0.01, 0.01}, 0.005);
  const auto n3 = static_cast<Eigen::Index>(3 * beam.mesh.nodes_m.size());
  std::mt19937 random(7);
  std::normal_distribution<double> normal(0.0, 1e-3);
  Eigen::MatrixXd directions(n3, 3);
  for (Eigen::Index i = 0; i < directions.size(); ++i) directions.data()[i] = normal(random);
  for (std::int32_t node : beam.scene.fixed_nodes) directions.middleRows(3 * node, 3).setZero();
  Eigen::MatrixXd snapshots(n3, 7);
  for (int k = 0; k < 7; ++k)
    snapshots.col(k) = directions * Eigen::Vector3d(std::sin(k + 1.0), std::cos(2.0 * k), 0.1 * k);
  ReductionOptions options;
  options.basis_size = 3;
  const std::span<const double> values(snapshots.data(), static_cast<std::size_t>(snapshots.size()));
  const auto basis = make_pod_basis(beam.mesh, beam.scene, linear_options(), options, values, 7);
  ASSERT_TRUE(basis.ok()) << basis.error().describe();
  const TetFemModel model = make_tet_fem_model(beam.mesh, beam.scene, linear_options()).value();
  const Eigen::VectorXd mass = dof_masses(model);
  const Eigen::MatrixXd u = basis_matrix(basis.value());
  EXPECT_LT((u.transpose() * mass.asDiagonal() * u - Eigen::MatrixXd::Identity(3, 3)).cwiseAbs().maxCoeff(), 1e-10);
  for (int k = 0; k < 7; ++k) {
    const Eigen::VectorXd s = snapshots.col(k);
    const Eigen::VectorXd projected = u * (u.transpose() * mass.cwiseProduct(s));
    EXPECT_LT((projected - s).norm(), 1e-10 * s.norm()) << k;
  }
  EXPECT_NEAR(basis.value().column_values[2], 1.0, 1e-12);
  EXPECT_LT(basis.value().column_values[0], basis.value().column_values[1]);
  options.basis_size = 4;  // the snapshots span only three directions
  const auto too_large = make_pod_basis(beam.mesh, beam.scene, linear_options(), options, values, 7);
  ASSERT_FALSE(too_large.ok());
  EXPECT_EQ(too_large.error().field, "basis_size");
  const auto wrong_size = make_pod_basis(beam.mesh, beam.scene, linear_options(), options, values.first(10), 7);
  ASSERT_FALSE(wrong_size.ok());
  EXPECT_EQ(wrong_size.error().field, "snapshots_m");
}

}  // namespace
}  // namespace nav
