// The mass-spring tissue with Promayon's volume constraint: the enclosed-volume formula, no
// force under rigid motion, the volume kept under load (its run-time contract and extremes are
// tested with the other models').
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <vector>

#include "nav/mesh/geometry.hpp"
#include "nav/tissue/mass_spring_model.hpp"
#include "tissue/tissue_test_support.hpp"

namespace nav {
namespace {

using testing::box_mesh;
using testing::faces_where;
using testing::nodes_where;

/// A 2 x 2 x 4 cm column clamped at z = 0, pushed sideways on its top face.
struct SpringColumn {
  TetMesh mesh = box_mesh({0.02, 0.02, 0.04}, 0.005);
  TissueScene scene;
  SpringColumn() {
    scene.default_material = {5.0e3, 0.45, 1000.0};
    scene.gravity_m_s2 = {0.0, 0.0, 0.0};
    scene.fixed_nodes = nodes_where(mesh, 2, 0.0);
    scene.traction_triangles = faces_where(mesh, 2, 0.04);
  }
};

MassSpringOptions options_for(bool keep_volume) {
  MassSpringOptions options;
  options.step_s = 2e-4;
  options.damping_per_s = 20.0;
  options.keep_volume = keep_volume;
  return options;
}

/// Runs `steps` steps under a sideways traction and gravity; returns the data.
MassSpringData run(const MassSpringModel& model, int steps) {
  auto data = make_mass_spring_data(model).value();
  TissueInputs inputs;
  inputs.traction_pa = {20.0, 0.0, -60.0};
  for (int s = 0; s < steps; ++s) step(model, data, inputs);
  return data;
}

}  // namespace

// The enclosed volume of the box's boundary equals its volume (to 1e-12 relative).
TEST(MassSpring, EnclosedVolumeOfTheBoundaryIsTheMeshVolume) {
  const SpringColumn column;
  auto model = make_mass_spring_model(column.mesh, column.scene, options_for(true));
  ASSERT_TRUE(model.ok()) << model.error().describe();
  EXPECT_NEAR(model.value().rest_volume_m3(), 0.02 * 0.02 * 0.04, 1e-12 * 1.6e-5);
  EXPECT_NEAR(model.value().rest_volume_m3(), total_volume_m3(column.mesh), 1e-12 * 1.6e-5);
}

// Springs carry no force under a rigid rotation of 90 degrees plus a translation (1e-12 of
// k L): one step from a rotated state with zero velocity and no load leaves it in place.
TEST(MassSpring, RigidMotionCarriesNoForce) {
  SpringColumn column;
  column.scene.fixed_nodes.clear();
  auto model = make_mass_spring_model(column.mesh, column.scene, options_for(true));
  ASSERT_TRUE(model.ok());
  auto data = make_mass_spring_data(model.value()).value();
  const Eigen::Matrix3d r = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d(1.0, 1.0, 0.0).normalized()).toRotationMatrix();
  for (std::size_t n = 0; n < column.mesh.nodes_m.size(); ++n) {
    const Eigen::Vector3d moved =
        r * Eigen::Vector3d(column.mesh.nodes_m[n][0], column.mesh.nodes_m[n][1], column.mesh.nodes_m[n][2]) +
        Eigen::Vector3d(0.1, 0.0, -0.05);
    for (int i = 0; i < 3; ++i) data.positions_m[3 * n + i] = moved[i];
  }
  step(model.value(), data, TissueInputs{});
  EXPECT_TRUE(data.health.healthy());
  double worst_force_n = 0.0;
  for (double f : data.forces_n) worst_force_n = std::max(worst_force_n, std::abs(f));
  EXPECT_LT(worst_force_n, 1e-12 * model.value().tables().stiffness_n_m[0] * 0.005);
  EXPECT_LT(std::abs(data.volume_change_pct), 1e-10);
}

// Under a load that changes the unconstrained network's volume by more than 1 %, the
// constraint keeps the enclosed volume within 1e-9 % of rest after every step.
TEST(MassSpring, VolumeIsKeptUnderLoad) {
  const SpringColumn column;
  auto free_model = make_mass_spring_model(column.mesh, column.scene, options_for(false));
  auto kept_model = make_mass_spring_model(column.mesh, column.scene, options_for(true));
  ASSERT_TRUE(free_model.ok() && kept_model.ok());
  EXPECT_LT(kept_model.value().options().step_s, kept_model.value().stable_step_s());
  const MassSpringData free_data = run(free_model.value(), 1500);
  EXPECT_GT(std::abs(free_data.volume_change_pct), 1.0);
  auto kept = make_mass_spring_data(kept_model.value()).value();
  TissueInputs inputs;
  inputs.traction_pa = {20.0, 0.0, -60.0};
  double worst_pct = 0.0, moved_m = 0.0;
  for (int s = 0; s < 1500; ++s) {
    step(kept_model.value(), kept, inputs);
    worst_pct = std::max(worst_pct, std::abs(kept.volume_change_pct));
  }
  for (std::size_t i = 0; i < kept.positions_m.size(); ++i)
    moved_m =
        std::max(moved_m, std::abs(kept.positions_m[i] - kept_model.value().tables().supports.rest_positions_m()[i]));
  std::printf("volume change: unconstrained %.3f %%, constrained %.2e %% (largest displacement %.1f mm)\n",
              free_data.volume_change_pct, worst_pct, 1e3 * moved_m);
  EXPECT_LT(worst_pct, 1e-9);
  EXPECT_GT(moved_m, 0.002);
  EXPECT_TRUE(kept.health.healthy());
}

}  // namespace nav
