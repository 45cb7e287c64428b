// Picinbono's cylinder (digest 001, Figs. 3 and 5, Table 2): a cylinder clamped at its base and
// pushed sideways by a traction on its top face, in three load stages, solved to equilibrium
// by the quasi-static integrator for the linear law, St Venant-Kirchhoff, and St Venant-Kirchhoff
// with the incompressibility penalty. The volume changes must reproduce the ordering of Table 2
// (linear 7/28/63 %, StVK 0.3/1/2 %, StVK + penalty 0.2/0.5/1 %).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

#include "nav/mesh/geometry.hpp"
#include "nav/mesher/implicit_domain.hpp"
#include "nav/mesher/mesher.hpp"
#include "nav/tissue/tet_fem_model.hpp"

namespace nav {
namespace {

constexpr double kRadiusM = 0.01;
constexpr double kHeightM = 0.06;

/// The cylinder of radius kRadiusM around the z axis, z in [0, kHeightM].
TetMesh cylinder_mesh() {
  const auto field = [](const Point3& p) {
    return std::max(std::hypot(p[0], p[1]) - kRadiusM, std::abs(p[2] - 0.5 * kHeightM) - 0.5 * kHeightM);
  };
  const ImplicitDomain domain(field, {{-0.012, -0.012, -0.002}, {0.012, 0.012, 0.062}}, 0.02);
  MesherOptions options;
  options.element_size_m = 0.004;
  return make_tet_mesh(domain, options).value().mesh;
}

double mesh_volume_m3(const TetMesh& mesh, std::span<const double> x) {
  double volume_m3 = 0.0;
  const auto at = [&](std::int32_t node) {
    const std::size_t i = 3 * static_cast<std::size_t>(node);
    return Point3{x[i], x[i + 1], x[i + 2]};
  };
  for (const auto& tet : mesh.tets) volume_m3 += signed_tet_volume_m3(at(tet[0]), at(tet[1]), at(tet[2]), at(tet[3]));
  return volume_m3;
}

/// Volume change in % after each of the three load stages (sideways tractions in Pa).
std::vector<double> volume_changes_pct(const TetMesh& mesh, const TissueScene& scene,
                                       const TissueSolverOptions& options, const std::vector<double>& stages_pa) {
  auto model = make_tet_fem_model(mesh, scene, options);
  EXPECT_TRUE(model.ok()) << model.error().describe();
  auto data = make_tet_fem_data(model.value()).value();
  const double rest_m3 = mesh_volume_m3(mesh, data.positions_m);
  std::vector<double> changes;
  double previous_pa = 0.0;
  constexpr int kRampSteps = 10, kSettleSteps = 15;
  for (double stage_pa : stages_pa) {
    TissueInputs inputs;
    for (int s = 1; s <= kRampSteps + kSettleSteps; ++s) {
      const double fraction = std::min(1.0, static_cast<double>(s) / kRampSteps);
      inputs.traction_pa = {previous_pa + fraction * (stage_pa - previous_pa), 0.0, 0.0};
      step(model.value(), data, inputs);
    }
    EXPECT_LT(data.report.solver_relative_residual, 1e-3) << stage_pa << " Pa";
    EXPECT_EQ(data.report.inverted_elements, 0);
    changes.push_back(100.0 * std::abs(mesh_volume_m3(mesh, data.positions_m) - rest_m3) / rest_m3);
    previous_pa = stage_pa;
  }
  return changes;
}

}  // namespace

// Tractions of 40, 100 and 200 Pa bend the 6 cm cylinder (E 5 kPa, lambda = 10 mu as in
// Picinbono) to tip deflections of about 0.4, 1 and 2 times its height under linear beam theory.
// Accepted: at every stage linear > StVK > StVK + penalty, the linear change grows more than
// 5-fold from the first to the last stage and exceeds 10 % there, StVK stays under 5 %, and
// the penalty removes at least a third of StVK's change at the last stage.
TEST(StvkCylinder, VolumeChangeOrderingOfPicinbonoTable2) {
  const TetMesh mesh = cylinder_mesh();
  TissueScene scene;
  scene.default_material = {5.0e3, 10.0 / 22.0, 1000.0};
  scene.gravity_m_s2 = {0.0, 0.0, 0.0};
  const TetMeshBoundary boundary = extract_boundary(mesh);
  for (std::size_t n = 0; n < mesh.nodes_m.size(); ++n)
    if (mesh.nodes_m[n][2] < 1e-6) scene.fixed_nodes.push_back(static_cast<std::int32_t>(n));
  for (const auto& triangle : boundary.surface.triangles) {
    bool top = true;
    for (int a = 0; a < 3; ++a) top = top && boundary.surface.vertices_m[triangle[a]][2] > kHeightM - 1e-6;
    if (top)
      scene.traction_triangles.push_back({boundary.mesh_node_of_vertex[triangle[0]],
                                          boundary.mesh_node_of_vertex[triangle[1]],
                                          boundary.mesh_node_of_vertex[triangle[2]]});
  }
  ASSERT_GT(scene.fixed_nodes.size(), 10u);
  ASSERT_GE(scene.traction_triangles.size(), 8u);

  TissueSolverOptions options;
  options.integrator = Integrator::quasi_static;
  options.cg_iterations = 60;
  const std::vector<double> stages_pa{40.0, 100.0, 200.0};
  options.rotation = ElementRotation::none;
  const std::vector<double> linear = volume_changes_pct(mesh, scene, options, stages_pa);
  options.rotation = ElementRotation::corotational;
  options.law = ElementLaw::st_venant_kirchhoff;
  const std::vector<double> stvk = volume_changes_pct(mesh, scene, options, stages_pa);
  options.incompressibility_gain_pa = 1.0e6;
  const std::vector<double> penalty = volume_changes_pct(mesh, scene, options, stages_pa);
  for (std::size_t k = 0; k < stages_pa.size(); ++k) {
    std::printf("stage %zu (%.0f Pa): volume change linear %.2f %%, StVK %.3f %%, StVK + penalty %.3f %%\n", k,
                stages_pa[k], linear[k], stvk[k], penalty[k]);
    EXPECT_GT(linear[k], stvk[k]);
    EXPECT_GT(stvk[k], penalty[k]);
    EXPECT_LT(stvk[k], 5.0);
  }
  EXPECT_GT(linear[2], 5.0 * linear[0]);
  EXPECT_GT(linear[2], 10.0);
  EXPECT_LT(penalty[2], (2.0 / 3.0) * stvk[2]);
}

}  // namespace nav
