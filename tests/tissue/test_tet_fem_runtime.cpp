// Run-time contract of the tetrahedral FEM tissue: steps never allocate, repeat bitwise,
// refuse bad inputs with the state untouched, flag inverted elements and unstable explicit
// steps without producing NaN; init-time errors name the parameter or region at fault.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <vector>

#include "nav/tissue/node_selection.hpp"
#include "nav/tissue/tet_fem_model.hpp"
#include "support/allocation_guard.hpp"
#include "tissue/tissue_test_support.hpp"

namespace nav {
namespace {

using testing::box_mesh;
using testing::faces_where;
using testing::nodes_where;
using testing::state_hash;

/// A 2 x 2 x 6 cm block with every boundary condition and load in use.
struct BusyScene {
  TetMesh mesh = box_mesh({0.02, 0.02, 0.06}, 0.005);
  TissueScene scene;
  BusyScene() {
    scene.default_material = {3.0e3, 0.45, 1000.0};
    scene.fixed_nodes = nodes_where(mesh, 2, 0.0);
    scene.prescribed_nodes = nodes_where(mesh, 2, 0.06);
    scene.spring_nodes = nodes_where(mesh, 0, 0.0);
    scene.spring_stiffness_n_m = 50.0;
    scene.traction_triangles = faces_where(mesh, 0, 0.02);
    scene.probe_stiffness_n_m = 200.0;
  }
};

/// Inputs of step i of a scripted sequence: moving frame, breathing, probe, forces.
TissueInputs scripted_inputs(int i, std::span<const PointForce> forces) {
  TissueInputs inputs;
  const double phase = 0.1 * i;
  inputs.point_forces = forces;
  inputs.traction_pa = {5.0 * std::sin(phase), 0.0, 1.0};
  inputs.spring_frame.rotation_wxyz = {std::cos(0.05 * phase), 0.0, std::sin(0.05 * phase), 0.0};
  inputs.spring_frame.translation_m = {0.001 * phase, 0.0, 0.0};
  inputs.prescribed_displacement_m = {0.0, 0.002 * std::sin(phase), 0.0};
  inputs.probe = {true, {0.03 - 0.0005 * i, 0.01, 0.03}, 0.012};
  return inputs;
}

std::vector<TissueSolverOptions> every_configuration() {
  std::vector<TissueSolverOptions> all;
  for (Integrator integrator : {Integrator::implicit_euler, Integrator::quasi_static, Integrator::explicit_central_difference})
    for (LinearSolver solver : {LinearSolver::ldlt_warped, LinearSolver::cg_jacobi, LinearSolver::cg_block_jacobi})
      for (ElementRotation rotation : {ElementRotation::corotational, ElementRotation::none}) {
        TissueSolverOptions options;
        options.integrator = integrator;
        options.solver = solver;
        options.rotation = rotation;
        options.rayleigh_mass_per_s = 0.5;
        options.step_s = integrator == Integrator::explicit_central_difference ? 2e-4 : 0.01;
        if (integrator != Integrator::explicit_central_difference) options.rayleigh_stiffness_s = 0.01;
        all.push_back(options);
      }
  return all;
}

}  // namespace

TEST(TetFemRuntime, StepsNeverAllocateAndRepeatBitwise) {
  const BusyScene busy;
  const std::vector<PointForce> forces{{5, {0.0, 0.01, 0.0}}, {17, {0.0, 0.0, -0.02}}};
  for (const TissueSolverOptions& options : every_configuration()) {
    auto model = make_tet_fem_model(busy.mesh, busy.scene, options);
    ASSERT_TRUE(model.ok()) << model.error().describe();
    std::uint64_t hashes[2] = {0, 0};
    for (std::uint64_t& hash : hashes) {
      auto data = make_tet_fem_data(model.value());
      ASSERT_TRUE(data.ok());
      int steps_in_contact = 0;
      {
        testing::AllocationGuard guard;
        for (int i = 0; i < 20; ++i) {
          step(model.value(), data.value(), scripted_inputs(i, forces));
          steps_in_contact += data.value().report.probe_contacts > 0 ? 1 : 0;
        }
        EXPECT_EQ(guard.allocations(), 0u);
      }
      EXPECT_EQ(data.value().steps, 20);
      EXPECT_FALSE(data.value().health.has(HealthFlag::non_finite_state));
      EXPECT_GT(steps_in_contact, 0);
      hash = state_hash(data.value().positions_m, data.value().velocities_m_s);
    }
    EXPECT_EQ(hashes[0], hashes[1]) << "integrator " << static_cast<int>(options.integrator) << " solver "
                                    << static_cast<int>(options.solver);
  }
}

TEST(TetFemRuntime, BadInputsAreRefusedWithTheStateUntouched) {
  const BusyScene busy;
  auto model = make_tet_fem_model(busy.mesh, busy.scene, TissueSolverOptions{});
  ASSERT_TRUE(model.ok());
  auto data = make_tet_fem_data(model.value());
  for (int i = 0; i < 3; ++i) step(model.value(), data.value(), scripted_inputs(i, {}));
  const std::uint64_t before = state_hash(data.value().positions_m, data.value().velocities_m_s);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const std::vector<PointForce> nan_force{{3, {0.0, nan, 0.0}}};
  const std::vector<PointForce> bad_node{{static_cast<std::int32_t>(busy.mesh.nodes_m.size()), {0.0, 0.0, 0.0}}};
  const std::vector<PointForce> too_many(busy.scene.max_point_forces + 1);
  std::vector<TissueInputs> bad(7, scripted_inputs(3, {}));
  bad[0].point_forces = nan_force;
  bad[1].point_forces = bad_node;
  bad[2].point_forces = too_many;
  bad[3].traction_pa[2] = inf;
  bad[4].spring_frame.rotation_wxyz = {0.0, 0.0, 0.0, 0.0};
  bad[5].prescribed_displacement_m[0] = nan;
  bad[6].probe.radius_m = nan;
  testing::AllocationGuard guard;
  for (const TissueInputs& inputs : bad) {
    data.value().health.clear_all();
    step(model.value(), data.value(), inputs);
    EXPECT_TRUE(data.value().health.has(HealthFlag::bad_sample));
    EXPECT_EQ(state_hash(data.value().positions_m, data.value().velocities_m_s), before);
    EXPECT_EQ(data.value().steps, 3);
  }
  EXPECT_EQ(guard.allocations(), 0u);
}

// A load far beyond what the block can carry crushes elements through zero volume: the step
// flags them, keeps their last rotation, and the state stays finite.
TEST(TetFemRuntime, InvertingLoadsAreFlaggedWithoutNaN) {
  const TetMesh mesh = box_mesh({0.02, 0.02, 0.02}, 0.005);
  TissueScene scene;
  scene.default_material = {1.0e3, 0.3, 1000.0};
  scene.fixed_nodes = nodes_where(mesh, 2, 0.0);
  for (Integrator integrator : {Integrator::implicit_euler, Integrator::quasi_static}) {
    TissueSolverOptions options;
    options.integrator = integrator;
    auto model = make_tet_fem_model(mesh, scene, options);
    ASSERT_TRUE(model.ok());
    auto data = make_tet_fem_data(model.value());
    const std::vector<PointForce> crush{{static_cast<std::int32_t>(nodes_where(mesh, 2, 0.02)[4]), {0.0, 0.0, -50.0}}};
    TissueInputs inputs;
    inputs.point_forces = crush;
    bool flagged = false;
    for (int i = 0; i < 20; ++i) {
      step(model.value(), data.value(), inputs);
      flagged = flagged || data.value().health.has(HealthFlag::inverted_element);
      for (double x : data.value().positions_m) ASSERT_TRUE(std::isfinite(x));
    }
    EXPECT_TRUE(flagged);
  }
}

// The explicit step is stable below the reported limit and flagged (never NaN) above it.
TEST(TetFemRuntime, ExplicitStepBeyondTheStableLimitIsFlagged) {
  const TetMesh mesh = box_mesh({0.02, 0.02, 0.04}, 0.005);
  TissueScene scene;
  scene.default_material = {1.0e4, 0.3, 1000.0};
  scene.fixed_nodes = nodes_where(mesh, 2, 0.0);
  TissueSolverOptions options;
  options.integrator = Integrator::explicit_central_difference;
  const double limit_s = make_tet_fem_model(mesh, scene, options).value().stable_step_s();
  ASSERT_GT(limit_s, 0.0);
  std::printf("explicit stable step estimate %.4g ms\n", limit_s * 1e3);
  for (double fraction : {0.9, 1.2}) {
    options.step_s = fraction * limit_s;
    auto model = make_tet_fem_model(mesh, scene, options);
    auto data = make_tet_fem_data(model.value());
    double largest_m = 0.0;
    for (int i = 0; i < 3000; ++i) step(model.value(), data.value(), TissueInputs{});
    for (std::size_t k = 0; k < data.value().positions_m.size(); ++k) {
      ASSERT_TRUE(std::isfinite(data.value().positions_m[k]));
      largest_m = std::max(largest_m, std::abs(data.value().positions_m[k] - model.value().rest_positions_m()[k]));
    }
    if (fraction < 1.0) {
      EXPECT_TRUE(data.value().health.healthy());
      EXPECT_LT(largest_m, 0.01);  // the sag under gravity is a fraction of a millimetre
    } else {
      EXPECT_TRUE(data.value().health.has(HealthFlag::solver_not_converged));
      EXPECT_GT(largest_m, 0.01);  // it did blow up: the estimate is not too pessimistic
    }
  }
}

TEST(TetFemRuntime, InitErrorsNameTheParameterOrRegion) {
  const TetMesh mesh = box_mesh({0.01, 0.01, 0.01}, 0.005);
  auto field_of = [&](TissueScene scene, TissueSolverOptions options = {}) {
    auto model = make_tet_fem_model(mesh, scene, options);
    return model.ok() ? std::string("ok") : model.error().field;
  };
  TissueScene scene;
  scene.default_material.poisson_ratio = 0.5;
  EXPECT_EQ(field_of(scene), "default_material.poisson_ratio");
  scene.default_material = {0.0, 0.3, 1000.0};
  EXPECT_EQ(field_of(scene), "default_material.youngs_modulus_pa");
  scene.default_material = {1e3, 0.3, 1000.0};
  scene.region_materials = {{2, {1e3, 0.3, -1.0}}};
  EXPECT_EQ(field_of(scene), "region_materials[2].density_kg_m3");
  scene.region_materials.clear();
  scene.fixed_nodes = {-1};
  EXPECT_EQ(field_of(scene), "fixed_nodes");
  scene.fixed_nodes.clear();
  TissueSolverOptions quasi_static;
  quasi_static.integrator = Integrator::quasi_static;
  EXPECT_EQ(field_of(scene, quasi_static), "fixed_nodes");
  TissueSolverOptions bad_step;
  bad_step.step_s = 0.0;
  EXPECT_EQ(field_of(scene, bad_step), "step_s");
  EXPECT_EQ(field_of(scene), "ok");
  TetMesh inverted = mesh;
  std::swap(inverted.tets[2][0], inverted.tets[2][1]);
  auto model = make_tet_fem_model(inverted, scene, {});
  ASSERT_FALSE(model.ok());
  EXPECT_EQ(model.error().field, "tets");
  EXPECT_NE(model.error().message.find("element 2"), std::string::npos);
  auto empty_region = nodes_in_box(mesh, {{1.0, 1.0, 1.0}, {2.0, 2.0, 2.0}}, "diaphragm_box");
  ASSERT_FALSE(empty_region.ok());
  EXPECT_EQ(empty_region.error().field, "diaphragm_box");
  EXPECT_EQ(nodes_in_box(mesh, {{-1.0, -1.0, -1.0}, {0.001, 1.0, 1.0}}, "side").value().size(), 9u);
}

}  // namespace nav
