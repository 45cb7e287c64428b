// Verification of the small-displacement static solver against analytic solutions.
#include "nav/tissue/linear_elastic_static.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "nav/mesh/geometry.hpp"
#include "nav/mesh/validation.hpp"
#include "tissue/tissue_test_support.hpp"

namespace nav {
namespace {

constexpr double kWidthM = 0.02;
constexpr double kLengthM = 0.1;

/// A square column along z: x, y in [0, w], z in [0, L].
TetMesh column_mesh(double element_size_m) { return testing::box_mesh({kWidthM, kWidthM, kLengthM}, element_size_m); }

using testing::nodes_where;

}  // namespace

/// Worst errors of the hanging column at one element size, relative to the free-end sag.
struct SagErrors {
  double axial = 0.0;    // worst |u_z - exact| / sag, over the nodes more than L/4 below the top
  double lateral = 0.0;  // worst |u_x|, |u_y| / sag (exactly 0 in the continuum)
  double free_end_sag_m = 0.0;
};

SagErrors hanging_column_errors(double element_size_m) {
  const TetMesh mesh = column_mesh(element_size_m);
  TissueScene scene;
  scene.default_material = {10'000.0, 0.0, 1000.0};
  scene.gravity_m_s2 = {0.0, 0.0, -9.81};
  scene.fixed_nodes = nodes_where(mesh, 2, kLengthM);
  auto solved = solve_linear_static(mesh, scene, TissueInputs{});
  EXPECT_TRUE(solved.ok());
  EXPECT_LT(solved.value().relative_residual, 1e-10);
  const double rho_g_over_e = 1000.0 * 9.81 / 10'000.0;
  const double sag_m = rho_g_over_e * kLengthM * kLengthM / 2.0;
  SagErrors errors;
  for (std::size_t n = 0; n < mesh.nodes_m.size(); ++n) {
    const double s = kLengthM - mesh.nodes_m[n][2];
    const Point3& u = solved.value().displacement_m[n];
    const double expected_m = -rho_g_over_e * (2 * kLengthM * s - s * s) / 2.0;
    if (s > 0.25 * kLengthM) errors.axial = std::max(errors.axial, std::abs(u[2] - expected_m) / sag_m);
    errors.lateral = std::max({errors.lateral, std::abs(u[0]) / sag_m, std::abs(u[1]) / sag_m});
    if (s > kLengthM - 1e-9) errors.free_end_sag_m = -u[2];
  }
  std::printf("hanging column, h = %.2f mm: free-end sag %.4f mm (analytic %.4f mm), axial error %.2e, lateral %.2e\n",
              element_size_m * 1e3, errors.free_end_sag_m * 1e3, sag_m * 1e3, errors.axial, errors.lateral);
  return errors;
}

// A column held at its top and hanging under its own weight, with nu = 0 so that the exact
// solution is one-dimensional: u_z(s) = -rho g (2 L s - s^2) / (2 E) at a distance s below
// the top, -rho g L^2 / (2 E) at the free end, no lateral motion. Linear elements on the
// (anisotropic) Kuhn lattice approach it as h shrinks.
TEST(LinearElasticStatic, HangingColumnConvergesToTheAnalyticSag) {
  const SagErrors coarse = hanging_column_errors(0.005);
  const SagErrors fine = hanging_column_errors(0.0025);
  EXPECT_LT(fine.axial, 0.012);
  EXPECT_LT(fine.lateral, 0.03);
  EXPECT_LT(fine.axial, coarse.axial / 1.7);
  EXPECT_LT(fine.lateral, coarse.lateral / 1.7);
}

// An end load F on a column held at its other end (nu = 0): uniform strain F / (E A), so the
// linear elements reproduce it exactly: u_z = F z / (E A).
TEST(LinearElasticStatic, EndLoadGivesTheExactUniformStretch) {
  const TetMesh mesh = column_mesh(0.005);
  TissueScene scene;
  scene.default_material = {10'000.0, 0.0, 1000.0};
  scene.gravity_m_s2 = {0.0, 0.0, 0.0};
  scene.fixed_nodes = nodes_where(mesh, 2, 0.0);
  std::vector<PointForce> forces;
  // Consistent nodal forces of a uniform traction on the face z = L: each boundary triangle
  // of that face gives a third of its force to each of its vertices.
  const double force_n = 0.5;
  const double traction_pa = force_n / (kWidthM * kWidthM);
  const TetMeshBoundary boundary = extract_boundary(mesh);
  for (const auto& triangle : boundary.surface.triangles) {
    std::array<Point3, 3> corners;
    for (int a = 0; a < 3; ++a) corners[a] = boundary.surface.vertices_m[triangle[a]];
    if (std::abs(corners[0][2] - kLengthM) > 1e-9 || std::abs(corners[1][2] - kLengthM) > 1e-9 ||
        std::abs(corners[2][2] - kLengthM) > 1e-9)
      continue;
    const double area_m2 = 0.5 * norm(cross(corners[1] - corners[0], corners[2] - corners[0]));
    for (int a = 0; a < 3; ++a)
      forces.push_back({boundary.mesh_node_of_vertex[triangle[a]], Point3{0.0, 0.0, traction_pa * area_m2 / 3.0}});
  }
  scene.max_point_forces = forces.size();
  TissueInputs loads;
  loads.point_forces = forces;
  auto solved = solve_linear_static(mesh, scene, loads);
  ASSERT_TRUE(solved.ok()) << solved.error().describe();
  const double strain = force_n / (10'000.0 * kWidthM * kWidthM);
  for (std::size_t n = 0; n < mesh.nodes_m.size(); ++n) {
    EXPECT_NEAR(solved.value().displacement_m[n][2], strain * mesh.nodes_m[n][2], 1e-9 * strain * kLengthM)
        << "node " << n;
  }
  // Uniaxial stress F / A everywhere.
  for (double stress_pa : solved.value().von_mises_stress_pa)
    EXPECT_NEAR(stress_pa, force_n / (kWidthM * kWidthM), 1e-6);
}

TEST(LinearElasticStatic, LoadsSuperpose) {
  const TetMesh mesh = column_mesh(0.01);
  TissueScene with_gravity;
  with_gravity.default_material = {10'000.0, 0.0, 1000.0};
  with_gravity.gravity_m_s2 = {0.0, 0.0, -9.81};
  with_gravity.fixed_nodes = nodes_where(mesh, 2, kLengthM);
  TissueScene without_gravity = with_gravity;
  without_gravity.gravity_m_s2 = {0.0, 0.0, 0.0};
  const PointForce force{0, Point3{0.01, -0.02, 0.03}};
  TissueInputs with_force;
  with_force.point_forces = std::span<const PointForce>(&force, 1);
  const auto a = solve_linear_static(mesh, with_gravity, TissueInputs{}).value();
  const auto b = solve_linear_static(mesh, without_gravity, with_force).value();
  const auto c = solve_linear_static(mesh, with_gravity, with_force).value();
  for (std::size_t n = 0; n < mesh.nodes_m.size(); ++n)
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR(c.displacement_m[n][k], a.displacement_m[n][k] + b.displacement_m[n][k],
                  1e-12 + 1e-9 * std::abs(c.displacement_m[n][k]));
}

TEST(LinearElasticStatic, RefusesUnsupportedOrBrokenInput) {
  TetMesh mesh = column_mesh(0.01);
  TissueScene scene;
  auto floating = solve_linear_static(mesh, scene, TissueInputs{});
  ASSERT_FALSE(floating.ok());
  EXPECT_EQ(floating.error().field, "fixed_nodes");

  scene.fixed_nodes = {static_cast<std::int32_t>(mesh.nodes_m.size())};
  EXPECT_EQ(solve_linear_static(mesh, scene, TissueInputs{}).error().field, "fixed_nodes");

  scene.fixed_nodes = {0};
  TissueScene with_springs = scene;
  with_springs.spring_nodes = {1};
  EXPECT_EQ(solve_linear_static(mesh, with_springs, TissueInputs{}).error().field, "spring_nodes");
  TissueInputs with_probe;
  with_probe.probe.active = true;
  EXPECT_EQ(solve_linear_static(mesh, scene, with_probe).error().field, "probe");

  std::swap(mesh.tets[3][0], mesh.tets[3][1]);  // turn one element inside out
  auto inverted = solve_linear_static(mesh, scene, TissueInputs{});
  ASSERT_FALSE(inverted.ok());
  EXPECT_NE(inverted.error().message.find("element 3"), std::string::npos) << inverted.error().describe();
}

}  // namespace nav
