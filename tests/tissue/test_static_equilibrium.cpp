// Verification of solve_static, the static solve of every elastic law: against the analytic
// uniform stretch, against the linear static solver's own assembly, and against each other; and
// of its Newton solve's cutbacks (newton_static.hpp).
#include "nav/tissue/static_equilibrium.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "nav/tissue/linear_elastic_static.hpp"
#include "nav/tissue/newton_static.hpp"
#include "tissue/tissue_test_support.hpp"

namespace nav {
namespace {

using testing::box_mesh;
using testing::faces_where;
using testing::max_abs;
using testing::nodes_where;

constexpr StaticLaw kLaws[] = {StaticLaw::linear, StaticLaw::corotational, StaticLaw::st_venant_kirchhoff,
                               StaticLaw::neo_hookean};

/// A 2 x 2 x 10 cm column of elements `element_size_m` held at z = 0, with nu = 0 and no gravity.
struct Column {
  TetMesh mesh;
  TissueScene scene;
  explicit Column(double element_size_m = 0.005) : mesh(box_mesh({0.02, 0.02, 0.1}, element_size_m)) {
    scene.default_material = {10'000.0, 0.0, 1000.0};
    scene.gravity_m_s2 = {0.0, 0.0, 0.0};
    scene.fixed_nodes = nodes_where(mesh, 2, 0.0);
  }
};

}  // namespace

// A traction t pulling the free end of a column (nu = 0) gives the uniform uniaxial stress t:
// u_z = t z / E, exact for linear elements under the linear law, and within the strain (1e-4)
// under the others. The reactions carry the load, and the stress is t in every element.
TEST(StaticEquilibrium, EndTractionGivesTheAnalyticStretchUnderEveryLaw) {
  Column column;
  column.scene.traction_triangles = faces_where(column.mesh, 2, 0.1);
  TissueInputs loads;
  const double traction_pa = 1.0;  // strain 1e-4
  loads.traction_pa = {0.0, 0.0, traction_pa};
  for (StaticLaw law : kLaws) {
    SCOPED_TRACE(static_law_name(law));
    const auto solved = solve_static(column.mesh, column.scene, loads, law);
    ASSERT_TRUE(solved.ok()) << solved.error().describe();
    const StaticEquilibrium& answer = solved.value();
    const double tolerance = law == StaticLaw::linear ? 1e-9 : 2e-4;
    double worst = 0.0;
    for (std::size_t n = 0; n < column.mesh.nodes_m.size(); ++n) {
      const double expected_m = traction_pa * column.mesh.nodes_m[n][2] / 10'000.0;
      worst = std::max({worst, std::abs(answer.displacement_m[3 * n + 2] - expected_m),
                        std::abs(answer.displacement_m[3 * n]), std::abs(answer.displacement_m[3 * n + 1])});
    }
    const double end_m = traction_pa * 0.1 / 10'000.0;
    double reaction_z_n = 0.0;
    for (std::size_t n = 0; n < column.mesh.nodes_m.size(); ++n) reaction_z_n += answer.reaction_n[3 * n + 2];
    const auto [low, high] = std::minmax_element(answer.von_mises_stress_pa.begin(), answer.von_mises_stress_pa.end());
    std::printf(
        "%-12s end stretch %.6f mm (analytic %.6f), worst error %.2e of it, stress %.6f..%.6f Pa, "
        "reaction %.6f N, relative out-of-balance %.1e after %d iterations\n",
        static_law_name(law), 1e3 * answer.displacement_m[3 * nodes_where(column.mesh, 2, 0.1)[0] + 2], 1e3 * end_m,
        worst / end_m, *low, *high, reaction_z_n, answer.relative_out_of_balance, answer.iterations);
    EXPECT_LT(worst, tolerance * end_m);
    EXPECT_NEAR(*low, traction_pa, tolerance * traction_pa + 1e-6);
    EXPECT_NEAR(*high, traction_pa, tolerance * traction_pa + 1e-6);
    EXPECT_NEAR(reaction_z_n, -traction_pa * 0.02 * 0.02, 1e-6 * traction_pa * 0.02 * 0.02);
    EXPECT_LE(answer.relative_out_of_balance, 1e-6);
    EXPECT_LT(max_abs(answer.out_of_balance_n), 1e-6 * traction_pa * 0.02 * 0.02);
  }
}

// Under gravity across the column (a cantilever bending), the linear law's answer is the linear
// static solver's, which assembles and factors K itself.
TEST(StaticEquilibrium, LinearLawMatchesTheLinearStaticSolver) {
  Column column;
  column.scene.default_material = {10'000.0, 0.45, 1000.0};
  column.scene.gravity_m_s2 = {0.0, -0.981, 0.0};
  const auto solved = solve_static(column.mesh, column.scene, TissueInputs{}, StaticLaw::linear);
  ASSERT_TRUE(solved.ok()) << solved.error().describe();
  const auto reference = solve_linear_static(column.mesh, column.scene, TissueInputs{}).value();
  double worst_m = 0.0, tip_m = 0.0;
  for (std::size_t n = 0; n < column.mesh.nodes_m.size(); ++n)
    for (int c = 0; c < 3; ++c) {
      worst_m = std::max(worst_m, std::abs(solved.value().displacement_m[3 * n + c] - reference.displacement_m[n][c]));
      tip_m = std::max(tip_m, std::abs(reference.displacement_m[n][c]));
    }
  double worst_stress_pa = 0.0;
  for (std::size_t e = 0; e < column.mesh.tets.size(); ++e)
    worst_stress_pa =
        std::max(worst_stress_pa, std::abs(solved.value().von_mises_stress_pa[e] - reference.von_mises_stress_pa[e]));
  std::printf("cantilever tip %.3f mm; largest difference from solve_linear_static %.2e m, stress %.2e Pa\n",
              1e3 * tip_m, worst_m, worst_stress_pa);
  EXPECT_GT(tip_m, 1e-3);
  EXPECT_LT(worst_m, 1e-9 * tip_m + 1e-15);
  EXPECT_LT(worst_stress_pa, 1e-6 * max_abs(reference.von_mises_stress_pa));
}

// A cantilever bending 5 cm under its own weight: the three non-linear laws each reach their
// equilibrium, and agree with each other to a tenth of the tip's travel, while the linear law,
// which cannot rotate, is off by more than the non-linear ones differ.
TEST(StaticEquilibrium, NonLinearLawsAgreeOnALargeBend) {
  Column column(0.01);  // 2 elements through the thickness: the laws compared, not the bend
  column.scene.default_material = {10'000.0, 0.3, 1000.0};
  column.scene.gravity_m_s2 = {0.0, -3.0, 0.0};
  double tip_y_m[4] = {};
  for (int i = 0; i < 4; ++i) {
    const auto solved = solve_static(column.mesh, column.scene, TissueInputs{}, kLaws[i]);
    ASSERT_TRUE(solved.ok()) << static_law_name(kLaws[i]) << ": " << solved.error().describe();
    for (std::int32_t n : nodes_where(column.mesh, 2, 0.1))
      tip_y_m[i] = std::min(tip_y_m[i], solved.value().displacement_m[3 * static_cast<std::size_t>(n) + 1]);
    std::printf("%-12s tip %.2f mm, relative out-of-balance %.1e after %d iterations\n", static_law_name(kLaws[i]),
                1e3 * tip_y_m[i], solved.value().relative_out_of_balance, solved.value().iterations);
    EXPECT_LE(solved.value().relative_out_of_balance, 1e-6);
    // Newton (all but the corotational law) in one load increment: a wrong tangent would cost
    // tens of line-searched iterations, or fail.
    if (kLaws[i] != StaticLaw::corotational) {
      EXPECT_LE(solved.value().iterations, 12);
    }
  }
  const double reference_m = tip_y_m[3];
  EXPECT_LT(reference_m, -0.015);
  EXPECT_LT(std::abs(tip_y_m[1] - reference_m), 0.1 * std::abs(reference_m));
  EXPECT_LT(std::abs(tip_y_m[2] - reference_m), 0.1 * std::abs(reference_m));
  EXPECT_GT(std::abs(tip_y_m[0] - reference_m),
            std::max(std::abs(tip_y_m[1] - reference_m), std::abs(tip_y_m[2] - reference_m)));
}

// Newton held to 3 iterations an increment cannot take the large bend in one: the increment is
// halved until it can, and the answer is the one 8 increments reach; with no cutback allowed,
// an Error names the load fraction it stopped at.
TEST(StaticEquilibrium, AnIncrementNewtonCannotTakeIsHalvedAndTheAnswerIsUnchanged) {
  Column column(0.01);
  column.scene.default_material = {10'000.0, 0.3, 1000.0};
  column.scene.gravity_m_s2 = {0.0, -3.0, 0.0};
  NewtonStaticOptions eight;
  eight.load_increments = 8;
  const auto reference = solve_newton_static(column.mesh, column.scene, TissueInputs{}, {}, eight);
  ASSERT_TRUE(reference.ok()) << reference.error().describe();
  EXPECT_EQ(reference.value().cutbacks, 0);
  NewtonStaticOptions short_newton;
  short_newton.max_newton_iterations = 3;
  const auto cut = solve_newton_static(column.mesh, column.scene, TissueInputs{}, {}, short_newton);
  ASSERT_TRUE(cut.ok()) << cut.error().describe();
  double largest_m = 0.0, difference_m = 0.0;
  for (std::size_t i = 0; i < cut.value().positions_m.size(); ++i) {
    largest_m = std::max(largest_m, std::abs(reference.value().positions_m[i] - column.mesh.nodes_m[i / 3][i % 3]));
    difference_m = std::max(difference_m, std::abs(cut.value().positions_m[i] - reference.value().positions_m[i]));
  }
  std::printf(
      "3 iterations an increment: %d cutbacks, %d iterations; 8 increments: %d iterations; largest "
      "displacement %.2f mm, answers %.1e of it apart\n",
      cut.value().cutbacks, cut.value().newton_iterations, reference.value().newton_iterations, 1e3 * largest_m,
      difference_m / largest_m);
  EXPECT_GE(cut.value().cutbacks, 1);
  EXPECT_GT(largest_m, 0.015);
  EXPECT_LT(difference_m, 1e-6 * largest_m);
  short_newton.max_cutbacks = 0;
  const auto refused = solve_newton_static(column.mesh, column.scene, TissueInputs{}, {}, short_newton);
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.error().field, "max_cutbacks");
  EXPECT_NE(refused.error().message.find("load fraction 1"), std::string::npos) << refused.error().message;
}

// Bad options and a solve cut short are errors that say which and how far it got.
TEST(StaticEquilibrium, RefusesBadOptionsAndReportsNoConvergence) {
  Column column;
  column.scene.gravity_m_s2 = {0.0, -3.0, 0.0};
  StaticSolveOptions bad;
  bad.relative_tolerance = 0.0;
  const auto refused = solve_static(column.mesh, column.scene, TissueInputs{}, StaticLaw::corotational, bad);
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.error().field, "static_solve_options");
  StaticSolveOptions short_run;
  short_run.ramp_steps = 2;
  short_run.max_steps = 3;
  const auto cut = solve_static(column.mesh, column.scene, TissueInputs{}, StaticLaw::corotational, short_run);
  ASSERT_FALSE(cut.ok());
  EXPECT_EQ(cut.error().field, "max_steps");
  EXPECT_NE(cut.error().message.find("relative out-of-balance force"), std::string::npos) << cut.error().message;
}

}  // namespace nav
