// Stability of the tetrahedral FEM tissue at the extremes of its parameters: nearly
// incompressible material, very soft to very stiff tissue, a stiff vessel through soft
// parenchyma, tiny to huge steps, sliver elements. Every case must stay finite, and
// healthy unless the case says otherwise; each runs for the corotational, St Venant-Kirchhoff
// and St Venant-Kirchhoff + penalty laws.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "nav/mesh/geometry.hpp"
#include "nav/tissue/mass_spring_model.hpp"
#include "nav/tissue/tet_fem_model.hpp"
#include "tissue/tissue_test_support.hpp"

namespace nav {
namespace {

using testing::box_mesh;
using testing::nodes_where;

constexpr double kBeamLengthM = 0.1;
constexpr double kBeamWidthM = 0.02;

TetMesh beam_mesh() { return box_mesh({kBeamLengthM, kBeamWidthM, kBeamWidthM}, 0.005); }

TissueScene clamped_beam(const TetMesh& mesh, const ElasticMaterial& material) {
  TissueScene scene;
  scene.default_material = material;
  scene.fixed_nodes = nodes_where(mesh, 0, 0.0);
  return scene;
}

/// Runs `steps` steps of `model` (built from `mesh`) under gravity; returns the largest
/// displacement, all of it finite.
template <class Model>
double run_model(const TetMesh& mesh, const Model& model, int steps, HealthFlags& health) {
  auto data = testing::make_data(model);
  for (int i = 0; i < steps; ++i) step(model, data.value(), TissueInputs{});
  double largest_m = 0.0;
  for (std::size_t k = 0; k < data.value().positions_m.size(); ++k) {
    EXPECT_TRUE(std::isfinite(data.value().positions_m[k]));
    largest_m = std::max(largest_m, std::abs(data.value().positions_m[k] - mesh.nodes_m[k / 3][k % 3]));
  }
  EXPECT_FALSE(data.value().health.has(HealthFlag::non_finite_state));
  health = data.value().health;
  return largest_m;
}

double run(const TetMesh& mesh, const TissueScene& scene, const TissueSolverOptions& options, int steps,
           HealthFlags& health) {
  auto model = make_tet_fem_model(mesh, scene, options);
  EXPECT_TRUE(model.ok()) << model.error().describe();
  return run_model(mesh, model.value(), steps, health);
}

/// A mass-spring model of the scene at `fraction` of its stable step, damped 20/s, run for
/// `duration_s` under gravity.
double run_mass_spring(const TetMesh& mesh, const TissueScene& scene, double fraction, double duration_s,
                       HealthFlags& health) {
  MassSpringOptions options;
  options.damping_per_s = 20.0;
  options.step_s = fraction * make_mass_spring_model(mesh, scene, options).value().stable_step_s();
  const MassSpringModel model = make_mass_spring_model(mesh, scene, options).value();
  return run_model(mesh, model, static_cast<int>(std::ceil(duration_s / options.step_s)), health);
}

double worst_radius_ratio(const TetMesh& mesh) {
  double worst = 1.0;
  for (const auto& tet : mesh.tets)
    worst = std::min(worst, tet_radius_ratio(mesh.nodes_m[tet[0]], mesh.nodes_m[tet[1]], mesh.nodes_m[tet[2]],
                                             mesh.nodes_m[tet[3]]));
  return worst;
}

/// The beam of beam_mesh with its elements around the axis y = z = 1 cm in region 2 (a vessel),
/// the others in region 1.
TetMesh vessel_beam_mesh() {
  TetMesh mesh = beam_mesh();
  mesh.tet_regions.assign(mesh.tets.size(), 1);
  for (std::size_t e = 0; e < mesh.tets.size(); ++e) {
    Point3 centroid{0.0, 0.0, 0.0};
    for (std::int32_t node : mesh.tets[e]) centroid = centroid + 0.25 * mesh.nodes_m[node];
    if (std::abs(centroid[1] - 0.01) < 0.005 && std::abs(centroid[2] - 0.01) < 0.005) mesh.tet_regions[e] = 2;
  }
  return mesh;
}

/// The beam of beam_mesh with a node pushed towards a face until its worst element has a
/// radius ratio just above 5e-3.
TetMesh sliver_beam_mesh() {
  TetMesh mesh = beam_mesh();
  const std::int32_t node = nodes_where(mesh, 0, 0.05)[12];  // an interior node of the mid-section
  const Point3 start = mesh.nodes_m[node];
  double scale = 0.0;
  for (double trial = 0.0; trial < 1.0; trial += 0.001) {
    mesh.nodes_m[node] = start + Point3{trial * 0.005, trial * 0.0025, 0.0};
    bool positive = true;
    for (std::size_t e = 0; e < mesh.tets.size(); ++e) positive = positive && signed_tet_volume_m3(mesh, e) > 1e-15;
    if (!positive || worst_radius_ratio(mesh) < 5e-3) break;
    scale = trial;
  }
  mesh.nodes_m[node] = start + Point3{scale * 0.005, scale * 0.0025, 0.0};
  std::printf("sliver: worst radius ratio %.2e\n", worst_radius_ratio(mesh));
  return mesh;
}

/// The element law under test, and its name.
struct Law {
  const char* name;
  ElementLaw law;
  double incompressibility_gain_pa;
};

class TetFemExtremes : public ::testing::TestWithParam<Law> {
 protected:
  /// Implicit Euler with the law under test, mass damping 2/s, 60 CG iterations at most.
  TissueSolverOptions damped_implicit(LinearSolver solver = LinearSolver::ldlt_warped, double step_s = 0.01) const {
    TissueSolverOptions options = law_options();
    options.solver = solver;
    options.step_s = step_s;
    options.rayleigh_mass_per_s = 2.0;
    options.cg_iterations = 60;
    return options;
  }
  TissueSolverOptions law_options() const {
    TissueSolverOptions options;
    options.law = GetParam().law;
    options.incompressibility_gain_pa = GetParam().incompressibility_gain_pa;
    return options;
  }
};

// Sag of a clamped beam under gravity for nu = 0.45, 0.49, 0.499: finite and healthy. Bending
// hardly depends on nu in the continuum, but linear tetrahedra lock volumetrically as
// nu -> 0.5: the sag can only shrink (by at most 5 % noise upwards) and is printed.
TEST_P(TetFemExtremes, NearlyIncompressibleMaterialsStayStable) {
  const TetMesh mesh = beam_mesh();
  double reference_m = 0.0;
  for (double nu : {0.45, 0.49, 0.499}) {
    HealthFlags health;
    const double sag_m = run(mesh, clamped_beam(mesh, {1.0e6, nu, 1000.0}), damped_implicit(), 100, health);
    std::printf("nu = %.3f: largest displacement %.4f mm\n", nu, sag_m * 1e3);
    EXPECT_TRUE(health.healthy());
    if (reference_m == 0.0) reference_m = sag_m;
    EXPECT_GT(sag_m, 0.0);
    EXPECT_LT(sag_m, 1.05 * reference_m);
  }
}

// Young's modulus from 100 Pa (the beam cannot carry its own weight: elements invert and are
// flagged) to 1 MPa. No node may move further than free fall over the run, g T^2 / 2.
TEST_P(TetFemExtremes, SoftToStiffTissueStaysFinite) {
  const TetMesh mesh = beam_mesh();
  for (double youngs_pa : {1.0e2, 1.0e3, 1.0e4, 1.0e5, 1.0e6}) {
    HealthFlags health;
    const double largest_m = run(mesh, clamped_beam(mesh, {youngs_pa, 0.45, 1000.0}), damped_implicit(), 50, health);
    std::printf("E = %.0e Pa: largest displacement %.4f mm, flags 0x%x\n", youngs_pa, largest_m * 1e3, health.bits());
    EXPECT_LT(largest_m, 0.5 * 9.81 * 0.5 * 0.5);  // 50 steps of 10 ms
  }
}

// A vessel 10^4 times stiffer than the parenchyma runs along the beam: direct and CG solves
// stay finite and healthy, and the vessel carries the beam (smaller sag than without it).
TEST_P(TetFemExtremes, StiffVesselThroughSoftParenchyma) {
  const TetMesh mesh = vessel_beam_mesh();
  TissueScene scene = clamped_beam(mesh, {1.0e3, 0.45, 1000.0});
  HealthFlags health;
  const double soft_m = run(mesh, scene, damped_implicit(), 50, health);
  scene.region_materials = {{2, {1.0e7, 0.45, 1000.0}}};
  for (LinearSolver solver : {LinearSolver::ldlt_warped, LinearSolver::cg_block_jacobi}) {
    const double stiffened_m = run(mesh, scene, damped_implicit(solver), 50, health);
    std::printf(
        "stiffness ratio 1e4, solver %d: largest displacement %.4f mm (%.4f mm without the vessel), flags 0x%x\n",
        static_cast<int>(solver), stiffened_m * 1e3, soft_m * 1e3, health.bits());
    EXPECT_LT(stiffened_m, 0.5 * soft_m);
    EXPECT_FALSE(health.has(HealthFlag::inverted_element));
  }
}

// Implicit steps from 0.1 ms to 100 ms, undamped: stable at every size.
TEST_P(TetFemExtremes, ImplicitStepsFromTenthOfAMillisecondToATenthOfASecond) {
  const TetMesh mesh = beam_mesh();
  const TissueScene scene = clamped_beam(mesh, {1.0e5, 0.45, 1000.0});
  for (double step_s : {1e-4, 1e-3, 1e-2, 1e-1}) {
    for (LinearSolver solver : {LinearSolver::ldlt_warped, LinearSolver::cg_block_jacobi}) {
      TissueSolverOptions options = damped_implicit(solver, step_s);
      options.rayleigh_mass_per_s = 0.0;
      HealthFlags health;
      const double largest_m = run(mesh, scene, options, 30, health);
      EXPECT_FALSE(health.has(HealthFlag::inverted_element)) << step_s;
      EXPECT_LT(largest_m, 0.05) << step_s;
    }
  }
}

// An interior node pushed almost onto a face of one of its elements makes slivers (radius
// ratio below 1e-2): implicit steps stay finite and deform the beam as the regular mesh does
// (largest displacement within 15 % mid-swing); the explicit stable step shrinks with the sliver.
TEST_P(TetFemExtremes, SliverElementsStayStable) {
  const TetMesh regular = beam_mesh();
  const TetMesh mesh = sliver_beam_mesh();
  ASSERT_LT(worst_radius_ratio(mesh), 1e-2);
  ASSERT_GT(worst_radius_ratio(mesh), 1e-3);
  const TissueScene scene = clamped_beam(mesh, {1.0e5, 0.45, 1000.0});
  HealthFlags health;
  const double regular_m = run(regular, clamped_beam(regular, scene.default_material), damped_implicit(), 50, health);
  for (LinearSolver solver : {LinearSolver::ldlt_warped, LinearSolver::cg_block_jacobi}) {
    const double sliver_m = run(mesh, scene, damped_implicit(solver), 50, health);
    EXPECT_NEAR(sliver_m, regular_m, 0.15 * regular_m);
    EXPECT_FALSE(health.has(HealthFlag::inverted_element));
  }
  TissueSolverOptions explicit_options = law_options();
  explicit_options.integrator = Integrator::explicit_central_difference;
  const double sliver_limit_s = make_tet_fem_model(mesh, scene, explicit_options).value().stable_step_s();
  const double regular_limit_s =
      make_tet_fem_model(regular, clamped_beam(regular, scene.default_material), explicit_options)
          .value()
          .stable_step_s();
  std::printf("explicit stable step: %.3g ms regular, %.3g ms with the sliver\n", regular_limit_s * 1e3,
              sliver_limit_s * 1e3);
  EXPECT_LT(sliver_limit_s, regular_limit_s);
}

INSTANTIATE_TEST_SUITE_P(Laws, TetFemExtremes,
                         ::testing::Values(Law{"corotational", ElementLaw::linear_elastic, 0.0},
                                           Law{"stvk", ElementLaw::st_venant_kirchhoff, 0.0},
                                           Law{"stvk_penalty", ElementLaw::st_venant_kirchhoff, 1.0e5}),
                         [](const ::testing::TestParamInfo<Law>& info) { return std::string(info.param.name); });

// The mass-spring network at the same extremes (Poisson's ratio has no counterpart in it; the
// volume constraint stands in): Young's modulus from 100 Pa to 1 MPa, each run at 0.8 of its
// stable step for 0.25 s, finite and within free fall g T^2 / 2.
TEST(MassSpringExtremes, SoftToStiffTissueStaysFinite) {
  const TetMesh mesh = beam_mesh();
  for (double youngs_pa : {1.0e2, 1.0e3, 1.0e4, 1.0e5, 1.0e6}) {
    HealthFlags health;
    const double largest_m = run_mass_spring(mesh, clamped_beam(mesh, {youngs_pa, 0.45, 1000.0}), 0.8, 0.25, health);
    std::printf("mass-spring, E = %.0e Pa: largest displacement %.4f mm, flags 0x%x\n", youngs_pa, largest_m * 1e3,
                health.bits());
    EXPECT_LT(largest_m, 0.5 * 9.81 * 0.25 * 0.25);
    EXPECT_FALSE(health.has(HealthFlag::unstable_step));
  }
}

// A vessel 10^4 times stiffer than the parenchyma: the stable step shrinks (by about 100), the
// run stays finite and uninverted, and the vessel carries the beam.
TEST(MassSpringExtremes, StiffVesselThroughSoftParenchyma) {
  const TetMesh mesh = vessel_beam_mesh();
  TissueScene scene = clamped_beam(mesh, {1.0e3, 0.45, 1000.0});
  HealthFlags health;
  const double soft_m = run_mass_spring(mesh, scene, 0.8, 0.1, health);
  scene.region_materials = {{2, {1.0e7, 0.45, 1000.0}}};
  const double stiffened_m = run_mass_spring(mesh, scene, 0.8, 0.1, health);
  std::printf(
      "mass-spring, stiffness ratio 1e4: largest displacement %.4f mm (%.4f mm without the vessel), flags 0x%x\n",
      stiffened_m * 1e3, soft_m * 1e3, health.bits());
  EXPECT_LT(stiffened_m, 0.5 * soft_m);
  EXPECT_TRUE(health.healthy());
}

// Explicit steps from 0.1 ms to 100 ms: those above the stable step are flagged unstable_step
// (and their non-finite results rolled back, non_finite_state), the others are healthy; the
// state never holds a NaN.
TEST(MassSpringExtremes, StepsFromTenthOfAMillisecondToATenthOfASecond) {
  const TetMesh mesh = beam_mesh();
  const TissueScene scene = clamped_beam(mesh, {1.0e3, 0.45, 1000.0});
  for (double step_s : {1e-4, 1e-3, 1e-2, 1e-1}) {
    MassSpringOptions options;
    options.step_s = step_s;
    options.damping_per_s = 20.0;
    const MassSpringModel model = make_mass_spring_model(mesh, scene, options).value();
    auto data = make_mass_spring_data(model).value();
    for (int i = 0; i < 100; ++i) step(model, data, TissueInputs{});
    for (double x : data.positions_m) ASSERT_TRUE(std::isfinite(x)) << step_s;
    std::printf("mass-spring, step %.0e s (stable %.2e s): flags 0x%x\n", step_s, model.stable_step_s(),
                data.health.bits());
    EXPECT_EQ(data.health.has(HealthFlag::unstable_step), step_s > model.stable_step_s()) << step_s;
    if (step_s < model.stable_step_s()) {
      EXPECT_TRUE(data.health.healthy()) << step_s;
    }
  }
}

// A sliver (radius ratio about 5e-3) leaves the network finite, uninverted, and bending as the
// regular mesh does (largest displacement within 15 %).
TEST(MassSpringExtremes, SliverElementsStayStable) {
  const TetMesh regular = beam_mesh();
  const TetMesh mesh = sliver_beam_mesh();
  const ElasticMaterial material{1.0e5, 0.45, 1000.0};
  HealthFlags health;
  const double regular_m = run_mass_spring(regular, clamped_beam(regular, material), 0.8, 0.1, health);
  const double sliver_m = run_mass_spring(mesh, clamped_beam(mesh, material), 0.8, 0.1, health);
  std::printf("mass-spring, sliver: largest displacement %.4f mm (%.4f mm regular)\n", sliver_m * 1e3, regular_m * 1e3);
  EXPECT_NEAR(sliver_m, regular_m, 0.15 * regular_m);
  EXPECT_TRUE(health.healthy());
}

}  // namespace
}  // namespace nav
