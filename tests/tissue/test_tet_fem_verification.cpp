// Verification of the tetrahedral FEM tissue against analytic solutions: patch tests, rigid
// rotation, a cantilever against Timoshenko beam theory, and energy under implicit Euler.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "nav/tissue/tet_fem_kernels.hpp"
#include "nav/tissue/tet_fem_model.hpp"
#include "tissue/tissue_test_support.hpp"

namespace nav {
namespace {

using testing::box_mesh;
using testing::faces_where;
using testing::max_abs;
using testing::nodes_where;

TissueSolverOptions quasi_static_options(LinearSolver solver = LinearSolver::ldlt_warped) {
  TissueSolverOptions options;
  options.integrator = Integrator::quasi_static;
  options.solver = solver;
  options.cg_iterations = 200;
  return options;
}

/// Elastic forces of the whole mesh at positions x (identity rotations before the update).
std::vector<double> elastic_forces(const TetFemModel& model, TetFemData& data, std::span<const double> x) {
  const auto& tables = model.tables();
  detail::update_element_rotations(tables, x, data.element_rotations);
  std::vector<double> forces(x.size(), 0.0);
  detail::add_elastic_forces(tables, x, data.element_rotations, forces);
  return forces;
}

}  // namespace

// Patch test: under any linear displacement field u = G X + c the interior nodes carry no net
// elastic force (constant stress is in equilibrium), for linear and corotational elements.
// Tolerance: 1e-9 of the force scale E h^2 |G|.
TEST(TetFemVerification, LinearFieldsLeaveInteriorNodesInEquilibrium) {
  const TetMesh mesh = box_mesh({0.03, 0.03, 0.03}, 0.005);
  TissueScene scene;
  scene.default_material = {2.0e4, 0.35, 1000.0};
  const double gradient[3][3] = {{0.010, 0.004, -0.002}, {0.004, -0.006, 0.003}, {-0.002, 0.003, 0.008}};
  for (ElementRotation rotation : {ElementRotation::none, ElementRotation::corotational}) {
    TissueSolverOptions options;
    options.rotation = rotation;
    auto model = make_tet_fem_model(mesh, scene, options);
    ASSERT_TRUE(model.ok()) << model.error().describe();
    auto data = make_tet_fem_data(model.value());
    std::vector<double> x(3 * mesh.nodes_m.size());
    for (std::size_t n = 0; n < mesh.nodes_m.size(); ++n)
      for (int i = 0; i < 3; ++i) {
        x[3 * n + i] = mesh.nodes_m[n][i] + 1e-4;
        for (int j = 0; j < 3; ++j) x[3 * n + i] += gradient[i][j] * mesh.nodes_m[n][j];
      }
    const std::vector<double> forces = elastic_forces(model.value(), data.value(), x);
    const double scale_n = 2.0e4 * 0.005 * 0.005 * 0.01;
    double worst_interior = 0.0, worst_boundary = 0.0;
    for (std::size_t n = 0; n < mesh.nodes_m.size(); ++n) {
      bool interior = true;
      for (int i = 0; i < 3; ++i) interior = interior && mesh.nodes_m[n][i] > 1e-9 && mesh.nodes_m[n][i] < 0.03 - 1e-9;
      for (int i = 0; i < 3; ++i)
        (interior ? worst_interior : worst_boundary) =
            std::max(interior ? worst_interior : worst_boundary, std::abs(forces[3 * n + i]));
    }
    EXPECT_LT(worst_interior, 1e-9 * scale_n);
    EXPECT_GT(worst_boundary, 1e-2 * scale_n);  // the boundary does carry the traction
  }
}

// Patch test through the whole quasi-static pipeline: a column clamped at z = 0 and pulled by
// a uniform traction on z = L (nu = 0) stretches uniformly, u_z = F z / (E A), to 1e-7.
TEST(TetFemVerification, EndTractionGivesTheExactUniformStretch) {
  const double width_m = 0.02, length_m = 0.06, youngs_pa = 1.0e4, force_n = 0.02;
  const TetMesh mesh = box_mesh({width_m, width_m, length_m}, 0.005);
  TissueScene scene;
  scene.default_material = {youngs_pa, 0.0, 1000.0};
  scene.gravity_m_s2 = {0.0, 0.0, 0.0};
  scene.fixed_nodes = nodes_where(mesh, 2, 0.0);
  scene.traction_triangles = faces_where(mesh, 2, length_m);
  for (LinearSolver solver : {LinearSolver::ldlt_warped, LinearSolver::cg_block_jacobi}) {
    auto model = make_tet_fem_model(mesh, scene, quasi_static_options(solver));
    ASSERT_TRUE(model.ok()) << model.error().describe();
    auto data = make_tet_fem_data(model.value());
    TissueInputs inputs;
    inputs.traction_pa = {0.0, 0.0, force_n / (width_m * width_m)};
    for (int i = 0; i < 8; ++i) step(model.value(), data.value(), inputs);
    EXPECT_TRUE(data.value().health.healthy());
    const double strain = force_n / (youngs_pa * width_m * width_m);
    for (std::size_t n = 0; n < mesh.nodes_m.size(); ++n) {
      const double expected_m = strain * mesh.nodes_m[n][2];
      ASSERT_NEAR(data.value().positions_m[3 * n + 2] - mesh.nodes_m[n][2], expected_m, 1e-7 * strain * length_m) << n;
      ASSERT_NEAR(data.value().positions_m[3 * n] - mesh.nodes_m[n][0], 0.0, 1e-7 * strain * length_m) << n;
    }
  }
}

// A rigid rotation by 90 degrees about z: the corotational elements feel no strain (force
// below 1e-9 of E h^2, energy below 1e-12 J), while the linear model's spurious force is
// of the order of E h^2 and is printed.
TEST(TetFemVerification, RigidRotationIsStrainFreeOnlyForCorotational) {
  const TetMesh mesh = box_mesh({0.02, 0.02, 0.04}, 0.005);
  TissueScene scene;
  scene.default_material = {1.0e4, 0.3, 1000.0};
  std::vector<double> rotated(3 * mesh.nodes_m.size());
  for (std::size_t n = 0; n < mesh.nodes_m.size(); ++n) {
    rotated[3 * n] = -mesh.nodes_m[n][1] + 0.1;
    rotated[3 * n + 1] = mesh.nodes_m[n][0];
    rotated[3 * n + 2] = mesh.nodes_m[n][2] - 0.05;
  }
  const double scale_n = 1.0e4 * 0.005 * 0.005;
  for (ElementRotation rotation : {ElementRotation::corotational, ElementRotation::none}) {
    TissueSolverOptions options;
    options.rotation = rotation;
    auto model = make_tet_fem_model(mesh, scene, options);
    ASSERT_TRUE(model.ok());
    auto data = make_tet_fem_data(model.value());
    const double force_n = max_abs(elastic_forces(model.value(), data.value(), rotated));
    std::copy(rotated.begin(), rotated.end(), data.value().positions_m.begin());
    const double energy_j = elastic_energy_j(model.value(), data.value());
    if (rotation == ElementRotation::corotational) {
      EXPECT_LT(force_n, 1e-9 * scale_n);
      EXPECT_LT(energy_j, 1e-12);
    } else {
      std::printf("linear model under a 90 degree rotation: largest nodal force %.3g N (%.2f E h^2), energy %.3g J\n",
                  force_n, force_n / scale_n, energy_j);
      EXPECT_GT(force_n, 0.1 * scale_n);
    }
  }
}

/// Tip deflection of a cantilever of length L, width b (y) and thickness t (z), clamped at
/// x = 0 and loaded by a uniform shear traction on x = L, meshed at h.
double cantilever_tip_deflection_m(double element_size_m, const Point3& size_m, double youngs_pa, double poisson,
                                   double force_n) {
  const TetMesh mesh = box_mesh(size_m, element_size_m);
  TissueScene scene;
  scene.default_material = {youngs_pa, poisson, 1000.0};
  scene.gravity_m_s2 = {0.0, 0.0, 0.0};
  scene.fixed_nodes = nodes_where(mesh, 0, 0.0);
  scene.traction_triangles = faces_where(mesh, 0, size_m[0]);
  auto model = make_tet_fem_model(mesh, scene, quasi_static_options());
  EXPECT_TRUE(model.ok());
  auto data = make_tet_fem_data(model.value());
  TissueInputs inputs;
  inputs.traction_pa = {0.0, 0.0, -force_n / (size_m[1] * size_m[2])};
  for (int i = 0; i < 4; ++i) step(model.value(), data.value(), inputs);
  EXPECT_TRUE(data.value().health.healthy());
  const std::vector<std::int32_t> tip = nodes_where(mesh, 0, size_m[0]);
  double sum_m = 0.0;
  for (std::int32_t node : tip) sum_m += mesh.nodes_m[node][2] - data.value().positions_m[3 * node + 2];
  return sum_m / static_cast<double>(tip.size());
}

// A cantilever (L = 5 t, b = t / 4) under an end load against Timoshenko's beam,
// PL^3/(3EI) + PL/(kGA) with k = 10 (1 + nu) / (12 + 11 nu), at 4, 8 and 16 elements
// through the thickness: the error falls with refinement and is under 3 % at the finest
// (linear tetrahedra are too stiff in bending, so the coarse levels are far off).
TEST(TetFemVerification, CantileverConvergesToTimoshenko) {
  const double thickness_m = 0.02, width_m = 0.005, length_m = 0.1, youngs_pa = 1.0e5, poisson = 0.3, force_n = 1e-4;
  const double inertia_m4 = width_m * std::pow(thickness_m, 3) / 12.0;
  const double shear_pa = youngs_pa / (2.0 * (1.0 + poisson));
  const double shear_factor = 10.0 * (1.0 + poisson) / (12.0 + 11.0 * poisson);
  const double exact_m = force_n * std::pow(length_m, 3) / (3.0 * youngs_pa * inertia_m4) +
                         force_n * length_m / (shear_factor * shear_pa * width_m * thickness_m);
  double previous_error = 1.0;
  for (double divisions : {4.0, 8.0, 16.0}) {
    const double deflection_m = cantilever_tip_deflection_m(thickness_m / divisions, {length_m, width_m, thickness_m},
                                                            youngs_pa, poisson, force_n);
    const double error = std::abs(deflection_m - exact_m) / exact_m;
    std::printf("cantilever, %g elements through the thickness: tip %.5g mm, Timoshenko %.5g mm, error %.2f %%\n",
                divisions, deflection_m * 1e3, exact_m * 1e3, 100.0 * error);
    EXPECT_LT(error, previous_error);
    previous_error = error;
  }
  EXPECT_LT(previous_error, 0.03);
}

// Undamped implicit Euler never gains energy: a soft cantilever released under gravity swings
// through large rotations; kinetic + elastic + gravity energy never exceeds its initial value
// (by more than 1e-9 of the energy scale), for the warped direct solve and for CG.
TEST(TetFemVerification, UndampedImplicitEulerNeverGainsEnergy) {
  const TetMesh mesh = box_mesh({0.1, 0.02, 0.02}, 0.01);
  TissueScene scene;
  scene.default_material = {2.0e3, 0.3, 1000.0};
  scene.fixed_nodes = nodes_where(mesh, 0, 0.0);
  for (LinearSolver solver : {LinearSolver::ldlt_warped, LinearSolver::cg_block_jacobi}) {
    TissueSolverOptions options;
    options.solver = solver;
    options.step_s = 0.01;
    options.cg_iterations = 100;
    auto model = make_tet_fem_model(mesh, scene, options);
    ASSERT_TRUE(model.ok());
    auto data = make_tet_fem_data(model.value());
    auto total = [&] {
      return kinetic_energy_j(model.value(), data.value()) + elastic_energy_j(model.value(), data.value()) +
             gravity_energy_j(model.value(), data.value());
    };
    const double initial_j = total();
    double lowest_j = initial_j, worst_gain_j = -1.0;
    for (int i = 0; i < 100; ++i) {
      step(model.value(), data.value(), TissueInputs{});
      const double now_j = total();
      worst_gain_j = std::max(worst_gain_j, now_j - initial_j);
      lowest_j = std::min(lowest_j, now_j);
    }
    const double scale_j = initial_j - lowest_j;
    std::printf("solver %d: energy drop %.3g J, worst gain over the start %.3g J\n", static_cast<int>(solver), scale_j,
                worst_gain_j);
    EXPECT_GT(scale_j, 0.0);
    EXPECT_LT(worst_gain_j, 1e-9 * scale_j);
  }
}

}  // namespace nav
