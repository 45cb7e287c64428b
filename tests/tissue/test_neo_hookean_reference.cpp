// Verification of the neo-Hookean accuracy reference: uniaxial stretch and compression of a
// block with free lateral faces against the closed-form neo-Hookean stress-stretch relation,
// and the small-load limit against linear elasticity.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "nav/tissue/linear_elastic_static.hpp"
#include "nav/tissue/newton_static.hpp"
#include "tissue/tissue_test_support.hpp"

namespace nav {
namespace {

using testing::box_mesh;
using testing::nodes_where;

/// Lateral stretch t of a uniaxial stretch s with stress-free lateral faces:
/// mu (t - 1/t) + lambda ln(s t^2) / t = 0, by Newton's method.
double lateral_stretch(double s, const LameParameters& lame) {
  double t = 1.0;
  for (int i = 0; i < 50; ++i) {
    const double value = lame.mu_pa * (t - 1.0 / t) + lame.lambda_pa * std::log(s * t * t) / t;
    const double slope = lame.mu_pa * (1.0 + 1.0 / (t * t)) + lame.lambda_pa * (2.0 - std::log(s * t * t)) / (t * t);
    t -= value / slope;
  }
  return t;
}

}  // namespace

// A 1 cm cube on three symmetry planes (rollers on x = 0, y = 0, z = 0), its face x = L pulled
// to stretch s = 1.5 or pushed to 0.7, lateral faces free: the solution is homogeneous, so the
// mesh must reproduce x = s X, y = t Y, z = t Z to 1e-9 L and the total reaction on x = L must
// equal the nominal stress P11 = mu (s - 1/s) + lambda ln(s t^2) / s times L^2, to 1e-8.
TEST(NeoHookeanReference, UniaxialStretchMatchesClosedForm) {
  constexpr double kSideM = 0.01;
  const TetMesh mesh = box_mesh({kSideM, kSideM, kSideM}, 0.0025);
  TissueScene scene;
  scene.default_material = {5.0e3, 0.45, 1000.0};
  scene.gravity_m_s2 = {0.0, 0.0, 0.0};
  const LameParameters lame = lame_parameters(scene.default_material);
  for (double stretch : {1.5, 0.7}) {
    std::vector<DofConstraint> constraints;
    for (int axis = 0; axis < 3; ++axis)
      for (std::int32_t node : nodes_where(mesh, axis, 0.0)) constraints.push_back({node, axis, 0.0});
    const std::vector<std::int32_t> pulled = nodes_where(mesh, 0, kSideM);
    for (std::int32_t node : pulled) constraints.push_back({node, 0, (stretch - 1.0) * kSideM});
    const auto solution = solve_newton_static(mesh, scene, TissueInputs{}, constraints);
    ASSERT_TRUE(solution.ok()) << solution.error().describe();
    const double t = lateral_stretch(stretch, lame);
    const std::vector<double>& x = solution.value().positions_m;
    for (std::size_t n = 0; n < mesh.nodes_m.size(); ++n) {
      EXPECT_NEAR(x[3 * n], stretch * mesh.nodes_m[n][0], 1e-9 * kSideM);
      EXPECT_NEAR(x[3 * n + 1], t * mesh.nodes_m[n][1], 1e-9 * kSideM);
      EXPECT_NEAR(x[3 * n + 2], t * mesh.nodes_m[n][2], 1e-9 * kSideM);
    }
    double reaction_n = 0.0;
    for (std::int32_t node : pulled)
      reaction_n += solution.value().reaction_forces_n[3 * static_cast<std::size_t>(node)];
    const double nominal_pa =
        lame.mu_pa * (stretch - 1.0 / stretch) + lame.lambda_pa * std::log(stretch * t * t) / stretch;
    EXPECT_NEAR(reaction_n, nominal_pa * kSideM * kSideM, 1e-8 * std::abs(nominal_pa) * kSideM * kSideM) << stretch;
  }
}

// Under a small load the neo-Hookean equilibrium equals linear elasticity's: a 4 cm column
// (E 100 MPa) clamped at its base sags sideways under gravity by 3 um (rotation 1e-4 rad, so
// that the geometric non-linearity, of order rotation^2 L, is 1e-4 of the sag); the two agree
// to 1e-3 of the largest displacement.
TEST(NeoHookeanReference, SmallLoadLimitIsLinearElasticity) {
  const TetMesh mesh = box_mesh({0.01, 0.01, 0.04}, 0.0025);
  TissueScene scene;
  scene.default_material = {1.0e8, 0.3, 1000.0};
  scene.gravity_m_s2 = {9.81, 0.0, 0.0};
  scene.fixed_nodes = nodes_where(mesh, 2, 0.0);
  const auto reference = solve_newton_static(mesh, scene, TissueInputs{}, {});
  ASSERT_TRUE(reference.ok()) << reference.error().describe();
  const auto linear = solve_linear_static(mesh, scene, TissueInputs{});
  ASSERT_TRUE(linear.ok()) << linear.error().describe();
  double largest_m = 0.0, worst_m = 0.0;
  for (std::size_t n = 0; n < mesh.nodes_m.size(); ++n)
    for (int i = 0; i < 3; ++i) {
      const double u_m = reference.value().positions_m[3 * n + i] - mesh.nodes_m[n][i];
      largest_m = std::max(largest_m, std::abs(linear.value().displacement_m[n][i]));
      worst_m = std::max(worst_m, std::abs(u_m - linear.value().displacement_m[n][i]));
    }
  EXPECT_GT(largest_m, 1e-6);  // the load does deform it
  EXPECT_LT(worst_m, 1e-3 * largest_m);
}

}  // namespace nav
