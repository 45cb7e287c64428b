// Hyper-reduction of the internal forces: Lawson-Hanson NNLS against known solutions, a
// cubature with every tetrahedron weighted 1 equal to the full projection U^T f(U q + L d)
// (computed by the full-order model's element loop), and ECSW meeting its training tolerance
// with few samples.
#include <gtest/gtest.h>

#include <random>

#include "nav/reduced/nnls.hpp"
#include "nav/reduced/reduced_forces.hpp"
#include "nav/reduced/reduced_model.hpp"
#include "nav/reduced/reduction.hpp"
#include "nav/tissue/tet_fem_kernels.hpp"
#include "reduced/reduced_test_support.hpp"

namespace nav {
namespace {

using testing::basis_matrix;
using testing::BeamScene;
using testing::nodes_where;

TEST(Nnls, RecoversAKnownNonNegativeSolution) {
  std::mt19937 random(11);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  Eigen::MatrixXd a(40, 12);
  for (Eigen::Index i = 0; i < a.size(); ++i) a.data()[i] = uniform(random);
  Eigen::VectorXd expected(12);
  expected << 0.0, 1.5, 0.0, 0.2, 3.0, 0.0, 0.0, 0.7, 0.0, 0.0, 2.2, 0.1;
  const detail::NnlsResult result = detail::nnls(a, a * expected);
  EXPECT_TRUE(result.converged);
  EXPECT_LT((result.x - expected).cwiseAbs().maxCoeff(), 1e-10);
}

TEST(Nnls, AWarmStartFromFewerColumnsFindsTheSameSolutionInFewerIterations) {
  // As the cubature grows its selection: the solution on the first k columns starts the
  // problem on k + 1. Each warm start must land where a cold start does.
  std::mt19937 random(23);
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::MatrixXd a(60, 24);
  Eigen::VectorXd b(60);
  for (Eigen::Index i = 0; i < a.size(); ++i) a.data()[i] = normal(random);
  for (Eigen::Index i = 0; i < b.size(); ++i) b[i] = normal(random);
  Eigen::VectorXd warm;
  int cold_iterations = 0, warm_iterations = 0, positive = 0;
  for (Eigen::Index k = 1; k <= a.cols(); ++k) {
    const detail::NnlsResult cold = detail::nnls(a.leftCols(k), b);
    Eigen::VectorXd start = Eigen::VectorXd::Zero(k);
    start.head(warm.size()) = warm;
    const detail::NnlsResult result = detail::nnls(a.leftCols(k), b, start);
    ASSERT_TRUE(cold.converged && result.converged) << k << " columns";
    EXPECT_LT((result.x - cold.x).cwiseAbs().maxCoeff(), 1e-12 * (1.0 + cold.x.cwiseAbs().maxCoeff()))
        << k << " columns";
    warm = result.x;
    cold_iterations += cold.iterations;
    warm_iterations += result.iterations;
  }
  for (Eigen::Index j = 0; j < warm.size(); ++j) positive += warm[j] > 0.0;
  std::printf("[ nnls     ] 24 columns grown one at a time: %d outer iterations cold, %d warm; %d positive weights\n",
              cold_iterations, warm_iterations, positive);
  EXPECT_GT(positive, 4);  // a solution with both free and bound weights
  EXPECT_LT(positive, 24);
  EXPECT_LT(2 * warm_iterations, cold_iterations);  // cold: one per positive weight each time
}

TEST(Nnls, MeetsTheKktConditionsWhenTheUnconstrainedSolutionIsNegative) {
  // min |x - b| with x >= 0 is max(b, 0); with A = I plus a coupling the KKT conditions hold.
  Eigen::MatrixXd a = Eigen::MatrixXd::Identity(6, 6);
  Eigen::VectorXd b(6);
  b << 1.0, -2.0, 0.5, -0.1, 3.0, 0.0;
  EXPECT_LT((detail::nnls(a, b).x - b.cwiseMax(0.0)).cwiseAbs().maxCoeff(), 1e-14);
  std::mt19937 random(5);
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::MatrixXd c(30, 8);
  Eigen::VectorXd d(30);
  for (Eigen::Index i = 0; i < c.size(); ++i) c.data()[i] = normal(random);
  for (Eigen::Index i = 0; i < d.size(); ++i) d[i] = normal(random) - 0.5 * c.row(i).sum();  // pulls x negative
  const detail::NnlsResult result = detail::nnls(c, d);
  ASSERT_TRUE(result.converged);
  const Eigen::VectorXd gradient = c.transpose() * (d - c * result.x);
  int active = 0;
  for (Eigen::Index j = 0; j < 8; ++j) {
    EXPECT_GE(result.x[j], 0.0);
    if (result.x[j] > 0.0) {
      EXPECT_NEAR(gradient[j], 0.0, 1e-10);
    } else {
      EXPECT_LE(gradient[j], 1e-10);
      ++active;
    }
  }
  EXPECT_GT(active, 0);  // the random problem has a bound constraint in force
}

/// A beam with a prescribed end and springs, its 6 modes, and a state q, d.
struct ProjectionCase {
  BeamScene beam{{0.03, 0.01, 0.01}, 0.005};
  ReducedBasis basis;
  Eigen::VectorXd q;
  Eigen::Vector3d d{0.0004, -0.0006, 0.0009};
  ProjectionCase(const TissueSolverOptions& solver, ReducedForceKind kind) {
    beam.scene.prescribed_nodes = nodes_where(beam.mesh, 0, 0.03);
    ReductionOptions options;
    options.source = ReducedBasisSource::linear_modes;
    options.force_kind = kind;
    options.basis_size = 6;
    basis = make_modal_basis(beam.mesh, beam.scene, solver, options).value();
    basis.sample_tets.resize(beam.mesh.tets.size());
    for (std::size_t e = 0; e < beam.mesh.tets.size(); ++e) basis.sample_tets[e] = static_cast<std::int32_t>(e);
    basis.sample_weights.assign(beam.mesh.tets.size(), 1.0);
    q = Eigen::VectorXd(6);
    q << 0.02, -0.01, 0.015, 0.004, -0.006, 0.002;  // large: elements rotate and stretch
  }
};

/// U^T f_elastic(U q + L d) by the full-order model's element loop.
Eigen::VectorXd full_projection(const ProjectionCase& c, const TissueSolverOptions& solver) {
  const TetFemModel model = make_tet_fem_model(c.beam.mesh, c.beam.scene, solver).value();
  const auto& tables = model.tables();
  const Eigen::MatrixXd u = basis_matrix(c.basis);
  const auto n3 = u.rows();
  Eigen::VectorXd displacement = u * c.q;
  for (int k = 0; k < 3; ++k)
    displacement += c.d[k] * Eigen::Map<const Eigen::VectorXd>(c.basis.diaphragm_lift.data() + k * n3, n3);
  std::vector<double> x(static_cast<std::size_t>(n3)), rotations(9 * tables.tets.size(), 0.0),
      forces(static_cast<std::size_t>(n3), 0.0);
  for (Eigen::Index i = 0; i < n3; ++i)
    x[static_cast<std::size_t>(i)] = tables.rest_m[static_cast<std::size_t>(i)] + displacement[i];
  for (std::size_t e = 0; e < tables.tets.size(); ++e)
    for (int k = 0; k < 3; ++k) rotations[9 * e + 4 * k] = 1.0;
  detail::update_element_rotations(tables, x, rotations);
  detail::add_elastic_forces(tables, x, rotations, forces);
  return u.transpose() * Eigen::Map<const Eigen::VectorXd>(forces.data(), n3);
}

/// The reduced model's internal force at (q, d).
Eigen::VectorXd cubature_force(const ProjectionCase& c, const TissueSolverOptions& solver) {
  const ReducedModel model = make_reduced_model(c.beam.mesh, c.beam.scene, solver, c.basis, {}).value();
  auto data = make_reduced_data(model).value();
  Eigen::VectorXd force(6);
  const detail::ReducedState state{std::span<const double>(c.q.data(), 6), c.d.data()};
  detail::evaluate_internal_force(
      model.tables(), state,
      {data.sample_displacements, data.sample_rotations, data.sample_tangent_rows, data.monomials},
      std::span<double>(force.data(), 6), {});
  return force;
}

TEST(ForceReduction, EveryTetWeightedOneEqualsTheFullCorotationalProjection) {
  TissueSolverOptions solver;
  solver.integrator = Integrator::quasi_static;
  const ProjectionCase c(solver, ReducedForceKind::corotational_cubature);
  const Eigen::VectorXd expected = full_projection(c, solver);
  EXPECT_LT((cubature_force(c, solver) - expected).norm(), 1e-10 * expected.norm());
}

TEST(ForceReduction, EveryTetWeightedOneEqualsTheFullStvkProjection) {
  TissueSolverOptions solver;
  solver.integrator = Integrator::quasi_static;
  solver.law = ElementLaw::st_venant_kirchhoff;
  solver.incompressibility_gain_pa = 2.0e4;
  const ProjectionCase c(solver, ReducedForceKind::stvk_cubature);
  const Eigen::VectorXd expected = full_projection(c, solver);
  EXPECT_LT((cubature_force(c, solver) - expected).norm(), 1e-10 * expected.norm());
}

TEST(ForceReduction, EcswMeetsItsToleranceWithFewSamples) {
  BeamScene beam({0.06, 0.01, 0.01}, 0.005);
  TissueSolverOptions solver;
  solver.integrator = Integrator::quasi_static;
  solver.cg_iterations = 3;
  ReductionOptions options;
  options.source = ReducedBasisSource::linear_modes;
  options.basis_size = 6;
  options.max_cubature_samples = 60;
  options.cubature_relative_tolerance = 0.02;
  ReducedBasis basis = make_modal_basis(beam.mesh, beam.scene, solver, options).value();
  const TetFemModel full = make_tet_fem_model(beam.mesh, beam.scene, solver).value();
  const PointForce force{static_cast<std::int32_t>(beam.mesh.nodes_m.size() - 1), {0.0, 0.004, -0.006}};
  const auto snapshots = testing::ramp_snapshots(full, force, 8, 0.15);
  const auto status = add_force_reduction(beam.mesh, beam.scene, solver, options, snapshots, 8, basis);
  ASSERT_TRUE(status.ok()) << status.error().describe();
  std::printf("ECSW: %zu of %zu tetrahedra, training error %.4f\n", basis.sample_tets.size(), beam.mesh.tets.size(),
              basis.training_residual_bound);
  EXPECT_LE(basis.training_residual_bound, options.cubature_relative_tolerance);
  EXPECT_LE(static_cast<int>(basis.sample_tets.size()), options.max_cubature_samples);
  EXPECT_LT(basis.sample_tets.size(), beam.mesh.tets.size() / 4);
  for (double weight : basis.sample_weights) EXPECT_GT(weight, 0.0);
  ASSERT_EQ(basis.training_q_bound.size(), 6u);
  EXPECT_GT(*std::max_element(basis.training_q_bound.begin(), basis.training_q_bound.end()), 0.0);
}

}  // namespace
}  // namespace nav

namespace nav {
namespace {

/// A beam without prescribed nodes, 5 modes, the cubic polynomial of its St Venant-Kirchhoff force.
struct PolynomialCase {
  BeamScene beam{{0.03, 0.01, 0.01}, 0.005};
  TissueSolverOptions solver;
  ReducedBasis basis;
  PolynomialCase() {
    solver.integrator = Integrator::quasi_static;
    solver.law = ElementLaw::st_venant_kirchhoff;
    ReductionOptions options;
    options.source = ReducedBasisSource::linear_modes;
    options.force_kind = ReducedForceKind::stvk_cubic_polynomial;
    options.basis_size = 5;
    basis = make_modal_basis(beam.mesh, beam.scene, solver, options).value();
    std::vector<double> snapshots(basis.basis.begin(), basis.basis.end());  // one snapshot per mode
    for (double& value : snapshots) value *= 0.01;
    const auto status = add_force_reduction(beam.mesh, beam.scene, solver, options, snapshots, 5, basis);
    EXPECT_TRUE(status.ok()) << status.error().describe();
  }
};

TEST(ForceReduction, CubicPolynomialEqualsTheDirectStvkProjection) {
  const PolynomialCase c;
  ProjectionCase direct(c.solver, ReducedForceKind::stvk_cubature);  // for full_projection's inputs
  direct.beam = c.beam;
  direct.basis = c.basis;
  direct.basis.diaphragm_lift.clear();
  direct.q = Eigen::VectorXd(5);
  direct.q << 0.03, -0.02, 0.01, 0.006, -0.004;  // large: the quadratic and cubic terms matter
  direct.d.setZero();
  const Eigen::VectorXd expected = full_projection(direct, c.solver);
  const ReducedModel model = make_reduced_model(c.beam.mesh, c.beam.scene, c.solver, c.basis, {}).value();
  auto data = make_reduced_data(model).value();
  Eigen::VectorXd force(5);
  Eigen::MatrixXd tangent(5, 5);
  const double zero[3] = {0.0, 0.0, 0.0};
  const detail::ForceScratch scratch{data.sample_displacements, data.sample_rotations, data.sample_tangent_rows,
                                     data.monomials};
  detail::evaluate_internal_force(model.tables(), {std::span<const double>(direct.q.data(), 5), zero}, scratch,
                                  std::span<double>(force.data(), 5), std::span<double>(tangent.data(), 25));
  EXPECT_LT((force - expected).norm(), 1e-10 * expected.norm());
  // The tangent is -df/dq: central differences of the polynomial force agree to 1e-6.
  for (int j = 0; j < 5; ++j) {
    Eigen::VectorXd plus = direct.q, minus = direct.q, f_plus(5), f_minus(5);
    plus[j] += 1e-6;
    minus[j] -= 1e-6;
    detail::evaluate_internal_force(model.tables(), {std::span<const double>(plus.data(), 5), zero}, scratch,
                                    std::span<double>(f_plus.data(), 5), {});
    detail::evaluate_internal_force(model.tables(), {std::span<const double>(minus.data(), 5), zero}, scratch,
                                    std::span<double>(f_minus.data(), 5), {});
    const Eigen::VectorXd column = -(f_plus - f_minus) / 2e-6;
    EXPECT_LT((tangent.col(j) - column).norm(), 1e-6 * tangent.norm()) << j;  // tangent is symmetric: column = row
  }
}

TEST(ForceReduction, CubicPolynomialNeedsStvkWithoutPenalty) {
  PolynomialCase c;
  ReductionOptions options;
  options.force_kind = ReducedForceKind::stvk_cubic_polynomial;
  TissueSolverOptions penalty = c.solver;
  penalty.incompressibility_gain_pa = 1e4;
  const std::vector<double> snapshots(
      c.basis.basis.begin(), c.basis.basis.begin() + static_cast<std::ptrdiff_t>(3 * c.beam.mesh.nodes_m.size()));
  EXPECT_EQ(add_force_reduction(c.beam.mesh, c.beam.scene, penalty, options, snapshots, 1, c.basis).error().field,
            "incompressibility_gain_pa");
  c.basis.polynomial_coefficients.pop_back();
  EXPECT_EQ(make_reduced_model(c.beam.mesh, c.beam.scene, c.solver, c.basis, {}).error().field,
            "polynomial_coefficients");
}

}  // namespace
}  // namespace nav
