// Run-time contract of every tissue model (tetrahedral FEM with each element law, integrator
// and solver, and the mass-spring model): steps never allocate, repeat bitwise, refuse bad
// inputs with the state untouched, flag inverted elements and unstable explicit steps without
// producing NaN; init-time errors name the parameter or region at fault.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <string>
#include <vector>

#include "nav/tissue/mass_spring_model.hpp"
#include "nav/tissue/node_selection.hpp"
#include "nav/tissue/tet_fem_model.hpp"
#include "support/allocation_guard.hpp"
#include "tissue/tissue_test_support.hpp"

namespace nav {
namespace {

using testing::bits_hash;
using testing::box_mesh;
using testing::BusyBoxScene;
using testing::make_data;
using testing::nodes_where;

/// Inputs of step i of a scripted sequence: load ramp, moving frame, breathing, probe, forces.
TissueInputs scripted_inputs(int i, std::span<const PointForce> forces) {
  TissueInputs inputs;
  const double phase = 0.1 * i;
  inputs.load_scale = std::min(1.0, 0.2 * (i + 1));
  inputs.point_forces = forces;
  inputs.traction_pa = {5.0 * std::sin(phase), 0.0, 1.0};
  inputs.spring_frame.rotation_wxyz = {std::cos(0.05 * phase), 0.0, std::sin(0.05 * phase), 0.0};
  inputs.spring_frame.translation_m = {0.001 * phase, 0.0, 0.0};
  inputs.prescribed_displacement_m = {0.0, 0.002 * std::sin(phase), 0.0};
  inputs.probe = {true, {0.03 - 0.0005 * i, 0.01, 0.03}, 0.012};
  return inputs;
}

/// The element laws of the tetrahedral FEM, by name.
struct RuntimeLaw {
  const char* name;
  ElementLaw law;
  ElementRotation rotation;
  double incompressibility_gain_pa;
};
constexpr RuntimeLaw kLaws[] = {
    {"linear", ElementLaw::linear_elastic, ElementRotation::none, 0.0},
    {"corotational", ElementLaw::linear_elastic, ElementRotation::corotational, 0.0},
    {"stvk", ElementLaw::st_venant_kirchhoff, ElementRotation::corotational, 0.0},
    {"stvk_penalty", ElementLaw::st_venant_kirchhoff, ElementRotation::corotational, 1.0e5}};

TissueSolverOptions options_for(const RuntimeLaw& law, Integrator integrator, LinearSolver solver) {
  TissueSolverOptions options;
  options.law = law.law;
  options.rotation = law.rotation;
  options.incompressibility_gain_pa = law.incompressibility_gain_pa;
  options.integrator = integrator;
  options.solver = solver;
  options.rayleigh_mass_per_s = 0.5;
  options.step_s = integrator == Integrator::explicit_central_difference ? 2e-4 : 0.01;
  if (integrator != Integrator::explicit_central_difference) options.rayleigh_stiffness_s = 0.01;
  return options;
}

/// Every law with every integrator, and every solver of the implicit and quasi-static ones
/// (the explicit integrator solves nothing), with a name for the failure messages.
std::vector<std::pair<std::string, TissueSolverOptions>> every_configuration() {
  std::vector<std::pair<std::string, TissueSolverOptions>> all;
  for (const RuntimeLaw& law : kLaws)
    for (Integrator integrator :
         {Integrator::implicit_euler, Integrator::quasi_static, Integrator::explicit_central_difference})
      for (LinearSolver solver : {LinearSolver::ldlt_warped, LinearSolver::cg_jacobi, LinearSolver::cg_block_jacobi}) {
        if (integrator == Integrator::explicit_central_difference && solver != LinearSolver::ldlt_warped) continue;
        all.emplace_back(std::string(law.name) + " integrator " + std::to_string(static_cast<int>(integrator)) +
                             " solver " + std::to_string(static_cast<int>(solver)),
                         options_for(law, integrator, solver));
      }
  return all;
}

/// The contract of one model on the busy scene: two runs of 20 scripted steps allocate nothing
/// and end in bitwise-equal states, in contact with the probe, finite; then every kind of bad
/// input is refused with the state untouched.
template <class Model>
void expect_runtime_contract(const Model& model, std::size_t node_count, std::size_t max_point_forces,
                             const std::string& what) {
  SCOPED_TRACE(what);
  const std::vector<PointForce> forces{{5, {0.0, 0.01, 0.0}}, {17, {0.0, 0.0, -0.02}}};
  std::uint64_t hashes[2] = {0, 0};
  for (std::uint64_t& hash : hashes) {
    auto data = make_data(model);
    ASSERT_TRUE(data.ok());
    int steps_in_contact = 0;
    {
      testing::AllocationGuard guard;
      for (int i = 0; i < 20; ++i) {
        step(model, data.value(), scripted_inputs(i, forces));
        steps_in_contact += data.value().report.probe_contacts > 0 ? 1 : 0;
      }
      EXPECT_EQ(guard.allocations(), 0u);
    }
    EXPECT_EQ(data.value().steps, 20);
    EXPECT_FALSE(data.value().health.has(HealthFlag::non_finite_state));
    EXPECT_FALSE(data.value().health.has(HealthFlag::unstable_step));
    EXPECT_GT(steps_in_contact, 0);
    hash = bits_hash({data.value().positions_m, data.value().velocities_m_s});
  }
  EXPECT_EQ(hashes[0], hashes[1]);

  auto data = make_data(model);
  for (int i = 0; i < 3; ++i) step(model, data.value(), scripted_inputs(i, forces));
  const std::uint64_t before = bits_hash({data.value().positions_m, data.value().velocities_m_s});
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const double inf = std::numeric_limits<double>::infinity();
  const std::vector<PointForce> nan_force{{3, {0.0, nan, 0.0}}};
  const std::vector<PointForce> inf_force{{3, {-inf, 0.0, 0.0}}};
  const std::vector<PointForce> bad_node{{static_cast<std::int32_t>(node_count), {0.0, 0.0, 0.0}}};
  const std::vector<PointForce> too_many(max_point_forces + 1);
  std::vector<TissueInputs> bad(10, scripted_inputs(3, {}));
  bad[0].point_forces = nan_force;
  bad[1].point_forces = inf_force;
  bad[2].point_forces = bad_node;
  bad[3].point_forces = too_many;
  bad[4].traction_pa[2] = inf;
  bad[5].spring_frame.rotation_wxyz = {0.0, 0.0, 0.0, 0.0};
  bad[6].prescribed_displacement_m[0] = nan;
  bad[7].probe.radius_m = nan;
  bad[8].load_scale = nan;
  bad[9].spring_frame.translation_m[1] = -inf;
  testing::AllocationGuard guard;
  for (std::size_t k = 0; k < bad.size(); ++k) {
    data.value().health.clear_all();
    step(model, data.value(), bad[k]);
    EXPECT_TRUE(data.value().health.has(HealthFlag::bad_sample)) << "bad input " << k;
    EXPECT_EQ(bits_hash({data.value().positions_m, data.value().velocities_m_s}), before) << "bad input " << k;
    EXPECT_EQ(data.value().steps, 3);
  }
  EXPECT_EQ(guard.allocations(), 0u);
}

}  // namespace

TEST(TissueRuntime, EveryTetFemConfigurationKeepsTheContract) {
  const BusyBoxScene busy;
  for (const auto& [name, options] : every_configuration()) {
    auto model = make_tet_fem_model(busy.mesh, busy.scene, options);
    ASSERT_TRUE(model.ok()) << name << ": " << model.error().describe();
    expect_runtime_contract(model.value(), busy.mesh.nodes_m.size(), busy.scene.max_point_forces, name);
  }
}

TEST(TissueRuntime, MassSpringKeepsTheContract) {
  const BusyBoxScene busy;
  MassSpringOptions options;
  options.damping_per_s = 0.5;
  options.step_s = 0.8 * make_mass_spring_model(busy.mesh, busy.scene, options).value().stable_step_s();
  auto model = make_mass_spring_model(busy.mesh, busy.scene, options);
  ASSERT_TRUE(model.ok()) << model.error().describe();
  expect_runtime_contract(model.value(), busy.mesh.nodes_m.size(), busy.scene.max_point_forces, "mass-spring");
}

// A load far beyond what the block can carry crushes elements through zero volume: the step
// flags them and the state stays finite, for every implicit law and the mass-spring network.
TEST(TissueRuntime, InvertingLoadsAreFlaggedWithoutNaN) {
  const TetMesh mesh = box_mesh({0.02, 0.02, 0.02}, 0.005);
  TissueScene scene;
  scene.default_material = {1.0e3, 0.3, 1000.0};
  scene.fixed_nodes = nodes_where(mesh, 2, 0.0);
  const std::vector<PointForce> crush{{static_cast<std::int32_t>(nodes_where(mesh, 2, 0.02)[4]), {0.0, 0.0, -50.0}}};
  TissueInputs inputs;
  inputs.point_forces = crush;
  const auto expect_flagged = [&](const auto& model, int steps, const std::string& what) {
    auto data = make_data(model);
    bool flagged = false;
    for (int i = 0; i < steps; ++i) {
      step(model, data.value(), inputs);
      flagged = flagged || data.value().health.has(HealthFlag::inverted_element);
      for (double x : data.value().positions_m) ASSERT_TRUE(std::isfinite(x)) << what;
    }
    EXPECT_TRUE(flagged) << what;
  };
  for (const RuntimeLaw& law : kLaws)
    for (Integrator integrator : {Integrator::implicit_euler, Integrator::quasi_static}) {
      auto model = make_tet_fem_model(mesh, scene, options_for(law, integrator, LinearSolver::ldlt_warped));
      ASSERT_TRUE(model.ok());
      expect_flagged(model.value(), 20,
                     std::string(law.name) + " integrator " + std::to_string(static_cast<int>(integrator)));
    }
  MassSpringOptions options;
  options.damping_per_s = 5.0;
  options.step_s = 0.8 * make_mass_spring_model(mesh, scene, options).value().stable_step_s();
  expect_flagged(make_mass_spring_model(mesh, scene, options).value(), 2000, "mass-spring");
}

// A conjugate-gradient solve cut short (one Jacobi-preconditioned iteration on a stiff column
// under a tip load) ends above its residual bound: the step raises solver_not_converged and
// reports the residual, the state stays finite. Given enough iterations, the same step ends
// below the bound and raises nothing. For the linear and corotational laws, implicit and
// quasi-static.
TEST(TissueRuntime, ACgSolveCutShortRaisesSolverNotConverged) {
  const TetMesh mesh = box_mesh({0.01, 0.01, 0.04}, 0.0025);
  TissueScene scene;
  scene.default_material = {5.0e4, 0.45, 1000.0};
  scene.fixed_nodes = nodes_where(mesh, 2, 0.0);
  const std::vector<PointForce> push{{nodes_where(mesh, 2, 0.04).front(), {0.5, 0.0, 0.0}}};
  TissueInputs inputs;
  inputs.point_forces = push;
  for (const RuntimeLaw& law : {kLaws[0], kLaws[1]})
    for (Integrator integrator : {Integrator::implicit_euler, Integrator::quasi_static}) {
      const std::string what = std::string(law.name) + " integrator " + std::to_string(static_cast<int>(integrator));
      TissueSolverOptions options = options_for(law, integrator, LinearSolver::cg_jacobi);
      double residual[2] = {0.0, 0.0};
      bool flagged[2] = {false, false};
      for (const int iterations : {1, 1000}) {
        options.cg_iterations = iterations;
        auto model = make_tet_fem_model(mesh, scene, options);
        ASSERT_TRUE(model.ok()) << what;
        auto data = make_data(model.value());
        ASSERT_TRUE(data.ok());
        step(model.value(), data.value(), inputs);
        const int k = iterations == 1 ? 0 : 1;
        residual[k] = data.value().report.solver_relative_residual;
        flagged[k] = data.value().health.has(HealthFlag::solver_not_converged);
        for (double x : data.value().positions_m) ASSERT_TRUE(std::isfinite(x)) << what;
      }
      std::printf("%s: relative residual after 1 CG iteration %.3g, after up to 1000 %.3g (bound %.3g)\n", what.c_str(),
                  residual[0], residual[1], options.cg_residual_bound);
      EXPECT_GT(residual[0], options.cg_residual_bound) << what;
      EXPECT_TRUE(flagged[0]) << what;
      EXPECT_LE(residual[1], options.cg_residual_bound) << what;
      EXPECT_FALSE(flagged[1]) << what;
    }
}

// The explicit step is stable below the reported limit and flagged unstable_step (never NaN)
// above it, for the linear, corotational, St Venant-Kirchhoff (+ penalty) laws and the
// mass-spring network. Above the limit the run blows up (to the rolled-back last finite
// state), but for the penalty law, whose limit is kept for element volume changes up to 10 %
// and is pessimistic for the fraction of a percent of this sag.
TEST(TissueRuntime, ExplicitStepBeyondTheStableLimitIsFlagged) {
  const TetMesh mesh = box_mesh({0.02, 0.02, 0.04}, 0.005);
  TissueScene scene;
  scene.default_material = {1.0e4, 0.3, 1000.0};
  scene.fixed_nodes = nodes_where(mesh, 2, 0.0);
  const TetFemModel rest_model = make_tet_fem_model(mesh, scene, {}).value();  // outlives rest_m
  const std::span<const double> rest_m = rest_model.rest_positions_m();
  const auto run = [&](const auto& model, double fraction, bool must_blow_up, const std::string& what) {
    auto data = make_data(model);
    double largest_m = 0.0;
    for (int i = 0; i < 3000; ++i) step(model, data.value(), TissueInputs{});
    for (std::size_t k = 0; k < data.value().positions_m.size(); ++k) {
      ASSERT_TRUE(std::isfinite(data.value().positions_m[k])) << what;
      largest_m = std::max(largest_m, std::abs(data.value().positions_m[k] - rest_m[k]));
    }
    if (fraction < 1.0) {
      EXPECT_TRUE(data.value().health.healthy()) << what;
      EXPECT_LT(largest_m, 0.01) << what;  // the sag under gravity is a fraction of a millimetre
    } else {
      EXPECT_TRUE(data.value().health.has(HealthFlag::unstable_step)) << what;
      if (must_blow_up) {
        EXPECT_GT(largest_m, 0.01) << what;  // it did: the estimate is not too pessimistic
      }
    }
  };
  for (const RuntimeLaw& law : kLaws) {
    TissueSolverOptions options = options_for(law, Integrator::explicit_central_difference, LinearSolver::ldlt_warped);
    options.rayleigh_mass_per_s = 0.0;
    const double limit_s = make_tet_fem_model(mesh, scene, options).value().stable_step_s();
    ASSERT_GT(limit_s, 0.0);
    std::printf("%s: explicit stable step estimate %.4g ms\n", law.name, limit_s * 1e3);
    for (double fraction : {0.9, 1.2}) {
      options.step_s = fraction * limit_s;
      run(make_tet_fem_model(mesh, scene, options).value(), fraction, law.incompressibility_gain_pa == 0.0, law.name);
    }
  }
  MassSpringOptions options;
  const double limit_s = make_mass_spring_model(mesh, scene, options).value().stable_step_s();
  std::printf("mass-spring: explicit stable step estimate %.4g ms\n", limit_s * 1e3);
  for (double fraction : {0.9, 3.0}) {
    options.step_s = fraction * limit_s;
    run(make_mass_spring_model(mesh, scene, options).value(), fraction, true, "mass-spring");
  }
}

TEST(TissueRuntime, InitErrorsNameTheParameterOrRegion) {
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
