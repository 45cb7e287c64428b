// Point forces spread over their node's patch (TissueScene::point_force_own_share): a force
// on a patch moves the tissue as its shares put on the nodes by hand do, and its point moves
// as their weighted mean; the rest response seen through the patches is the step's and
// reciprocal; the step stays allocation-free; a concentrated force that inverts elements on
// its node alone inverts none spread; shares outside (0, 1] are refused, and the models that
// keep forces on their nodes refuse a share below 1.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <vector>

#include "nav/mesh/geometry.hpp"
#include "nav/tissue/linear_elastic_static.hpp"
#include "nav/tissue/tet_fem_model.hpp"
#include "support/allocation_guard.hpp"
#include "tissue/tissue_test_support.hpp"

namespace nav {
namespace {

using testing::box_mesh;
using testing::nodes_where;

constexpr double kSideM = 0.04, kElementM = 0.01;

/// A 4 cm cube of 1 cm elements held at z = 0, without gravity, stepped quasi-statically with
/// the rest factor; `law` and the share as given.
struct Cube {
  TetMesh mesh = box_mesh({kSideM, kSideM, kSideM}, kElementM);
  TissueScene scene;
  TissueSolverOptions options;
  Cube(double own_share, ElementRotation rotation) {
    scene.gravity_m_s2 = {0.0, 0.0, 0.0};
    scene.fixed_nodes = nodes_where(mesh, 2, 0.0);
    scene.point_force_own_share = own_share;
    options.rotation = rotation;
    options.integrator = Integrator::quasi_static;
    options.solver = LinearSolver::ldlt_warped;
  }
  TetFemModel model() const { return make_tet_fem_model(mesh, scene, options).value(); }
  /// The node nearest `p_m`.
  std::int32_t node_at(const Point3& p_m) const {
    std::int32_t best = 0;
    for (std::size_t n = 0; n < mesh.nodes_m.size(); ++n)
      if (norm(mesh.nodes_m[n] - p_m) < norm(mesh.nodes_m[static_cast<std::size_t>(best)] - p_m))
        best = static_cast<std::int32_t>(n);
    return best;
  }
  /// The nodes sharing an element with `node`, without it.
  std::vector<std::int32_t> neighbours(std::int32_t node) const {
    std::vector<std::int32_t> out;
    for (const auto& tet : mesh.tets)
      if (std::find(tet.begin(), tet.end(), node) != tet.end())
        for (std::int32_t other : tet)
          if (other != node && std::find(out.begin(), out.end(), other) == out.end()) out.push_back(other);
    return out;
  }
};

TEST(PointForcePatches, AForceOnAPatchMovesTheTissueAsItsSharesOnTheNodesDo) {
  const Cube spread(0.5, ElementRotation::corotational), plain(1.0, ElementRotation::corotational);
  const std::int32_t node = spread.node_at({0.02, 0.02, kSideM});
  const std::vector<std::int32_t> ring = spread.neighbours(node);
  ASSERT_GE(ring.size(), 6u);
  const Point3 force_n{0.3, -0.2, -1.0};
  const auto scaled = [&force_n](double s) { return Point3{s * force_n[0], s * force_n[1], s * force_n[2]}; };
  std::vector<PointForce> shares{{node, scaled(0.5)}};
  for (std::int32_t other : ring) shares.push_back({other, scaled(0.5 / static_cast<double>(ring.size()))});
  TissueScene roomy = plain.scene;  // the shares by hand are more forces than the default 16
  roomy.max_point_forces = shares.size();
  const TetFemModel spread_model = spread.model(),
                    plain_model = make_tet_fem_model(plain.mesh, roomy, plain.options).value();
  TetFemData a = make_tet_fem_data(spread_model).value(), b = make_tet_fem_data(plain_model).value();
  const PointForce one{node, force_n};
  TissueInputs on_patch, by_hand;
  on_patch.point_forces = std::span<const PointForce>(&one, 1);
  by_hand.point_forces = shares;
  for (int s = 0; s < 5; ++s) {
    step(spread_model, a, on_patch);
    step(plain_model, b, by_hand);
  }
  std::vector<double> difference(a.positions_m.size());
  for (std::size_t i = 0; i < difference.size(); ++i) difference[i] = a.positions_m[i] - b.positions_m[i];
  std::vector<double> moved(a.positions_m.size());
  for (std::size_t i = 0; i < moved.size(); ++i) moved[i] = b.positions_m[i] - spread.mesh.nodes_m[i / 3][i % 3];
  std::printf("largest displacement %.3f mm, largest difference %.2e m\n", 1e3 * testing::max_abs(moved),
              testing::max_abs(difference));
  EXPECT_GT(testing::max_abs(moved), 1e-4);
  EXPECT_LT(testing::max_abs(difference), 1e-12 * std::max(1.0, 1e3 * testing::max_abs(moved)));
  // The force's point: half its node's displacement, half the mean of its neighbours'.
  std::vector<double> points(a.positions_m.size());
  point_displacements_m(spread_model, a, points);
  for (std::size_t c = 0; c < 3; ++c) {
    const auto at = [&](std::int32_t n) { return moved[3 * static_cast<std::size_t>(n) + c]; };
    double mean = 0.0;
    for (std::int32_t other : ring) mean += at(other) / static_cast<double>(ring.size());
    EXPECT_NEAR(points[3 * static_cast<std::size_t>(node) + c], 0.5 * at(node) + 0.5 * mean, 1e-12);
  }
}

TEST(PointForcePatches, TheRestResponseThroughThePatchesIsTheStepsAndReciprocal) {
  const Cube linear(0.5, ElementRotation::none);
  const TetFemModel model = linear.model();
  const std::int32_t a = linear.node_at({0.02, 0.02, kSideM}), b = linear.node_at({0.03, 0.01, 0.03});
  const std::size_t values = 3 * linear.mesh.nodes_m.size();
  std::vector<double> from_a(values), from_b(values), work(2 * static_cast<std::size_t>(model.free_dof_count()));
  ASSERT_TRUE(rest_step_response_m(model, a, 0, from_a, work));
  ASSERT_TRUE(rest_step_response_m(model, b, 2, from_b, work));
  // Reciprocity: a's point along z under a unit force on b along x, and the other way round.
  const double ab = from_a[3 * static_cast<std::size_t>(b) + 2], ba = from_b[3 * static_cast<std::size_t>(a)];
  std::printf("reciprocal responses %.6e and %.6e m/N\n", ab, ba);
  EXPECT_NE(ab, 0.0);
  EXPECT_NEAR(ab, ba, 1e-12 * std::abs(ab));
  // The step from rest under a unit force on a along x (linear elements: exact in one step).
  TetFemData data = make_tet_fem_data(model).value();
  const PointForce unit{a, {1.0, 0.0, 0.0}};
  TissueInputs inputs;
  inputs.point_forces = std::span<const PointForce>(&unit, 1);
  std::vector<double> points(values);
  testing::AllocationGuard guard;
  step(model, data, inputs);
  point_displacements_m(model, data, points);
  EXPECT_EQ(guard.allocations(), 0u);
  std::vector<double> difference(values);
  for (std::size_t i = 0; i < values; ++i) difference[i] = points[i] - from_a[i];
  EXPECT_LT(testing::max_abs(difference), 1e-9 * testing::max_abs(from_a));
}

// A needle's puncture force (1 N) on the top face's middle node of 1 cm liver elements inverts
// two of them; half of it on the node and half on its neighbours inverts none (0.8 N on the
// node alone inverts none either, 1.5 N spread inverts two: the margin is that of the demo).
TEST(PointForcePatches, AForceThatInvertsElementsOnItsNodeAloneInvertsNoneSpread) {
  int inverted[2] = {0, 0};
  const double shares[2] = {1.0, 0.5};
  for (int k = 0; k < 2; ++k) {
    const Cube cube(shares[k], ElementRotation::corotational);
    const TetFemModel model = cube.model();
    TetFemData data = make_tet_fem_data(model).value();
    const PointForce push{cube.node_at({0.02, 0.02, kSideM}), {0.0, 0.0, -1.0}};
    TissueInputs inputs;
    inputs.point_forces = std::span<const PointForce>(&push, 1);
    for (int s = 0; s < 20; ++s) {
      inputs.load_scale = std::min(1.0, 0.1 * (s + 1));
      step(model, data, inputs);
      inverted[k] = std::max(inverted[k], data.report.inverted_elements);
    }
  }
  std::printf("elements inverted under 1 N: %d on the node alone, %d spread\n", inverted[0], inverted[1]);
  EXPECT_GT(inverted[0], 0);
  EXPECT_EQ(inverted[1], 0);
}

TEST(PointForcePatches, SharesOutsideZeroToOneAreRefusedAndTheLinearSolveTakesOnlyOne) {
  for (double share : {0.0, -0.5, 1.5, std::numeric_limits<double>::quiet_NaN()}) {
    const Cube cube(share, ElementRotation::corotational);
    const auto model = make_tet_fem_model(cube.mesh, cube.scene, cube.options);
    ASSERT_FALSE(model.ok()) << share;
    EXPECT_EQ(model.error().field, "point_force_own_share");
  }
  const Cube cube(0.5, ElementRotation::none);
  const auto solved = solve_linear_static(cube.mesh, cube.scene, TissueInputs{});
  ASSERT_FALSE(solved.ok());
  EXPECT_EQ(solved.error().field, "point_force_own_share");
}

}  // namespace
}  // namespace nav
