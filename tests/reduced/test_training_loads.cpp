// Training and held-out load sets: seeded and repeatable, held-out points never training
// points, magnitudes as asked; their full-order static solutions agree with the independent
// linear static solver where displacements are small, and keep the supports.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>

#include "nav/mesh/geometry.hpp"
#include "nav/reduced/training_loads.hpp"
#include "nav/tissue/linear_elastic_static.hpp"
#include "tissue/tissue_test_support.hpp"

namespace nav {
namespace {

constexpr double kLengthM = 0.06;

/// A 2 x 2 x 6 cm column clamped at z = 0, gravity along -x (bending), stiff enough (1 MPa)
/// that its displacements stay small and corotational equals linear elasticity.
struct Column {
  TetMesh mesh = testing::box_mesh({0.02, 0.02, kLengthM}, 0.005);
  TissueScene scene;
  Column() {
    scene.default_material = {1.0e6, 0.3, 1000.0};
    scene.gravity_m_s2 = {-9.81, 0.0, 0.0};
    scene.fixed_nodes = testing::nodes_where(mesh, 2, 0.0);
  }
};

Point3 total_force(const TrainingLoad& load) {
  Point3 sum{};
  for (const PointForce& f : load.point_forces) sum = sum + f.force_n;
  return sum;
}

TEST(TrainingLoads, SetsAreSeededDisjointAndSizedAsAsked) {
  const Column column;
  const TissueScene scene = with_diaphragm(column.mesh, column.scene, 0.006);
  TrainingLoadOptions options;
  const auto training = make_training_loads(column.mesh, scene, options, LoadSet::training);
  const auto again = make_training_loads(column.mesh, scene, options, LoadSet::training);
  const auto held_out = make_training_loads(column.mesh, scene, options, LoadSet::held_out);
  ASSERT_EQ(training.size(), again.size());
  for (std::size_t k = 0; k < training.size(); ++k) {
    EXPECT_EQ(training[k].name, again[k].name);
    EXPECT_EQ(training[k].gravity_m_s2, again[k].gravity_m_s2);
    EXPECT_EQ(training[k].prescribed_displacement_m, again[k].prescribed_displacement_m);
    ASSERT_EQ(training[k].point_forces.size(), again[k].point_forces.size());
    for (std::size_t f = 0; f < training[k].point_forces.size(); ++f)
      EXPECT_EQ(training[k].point_forces[f].force_n, again[k].point_forces[f].force_n);
  }
  const auto count_of = [](const std::vector<TrainingLoad>& loads, const std::string& kind) {
    return std::count_if(loads.begin(), loads.end(), [&](const TrainingLoad& l) { return l.name.starts_with(kind); });
  };
  EXPECT_EQ(count_of(training, "gravity"), 2 + options.gravity_tilts);
  EXPECT_EQ(count_of(training, "push"), options.probe_pushes);
  EXPECT_EQ(count_of(training, "needle"), options.needle_forces);
  EXPECT_EQ(count_of(training, "diaphragm"), options.diaphragm_moves);
  EXPECT_EQ(count_of(held_out, "push"), (options.probe_pushes + 1) / 2);

  // The first force of a patch is at its sampled centre: held-out centres are new points.
  std::set<std::int32_t> training_centres;
  for (const TrainingLoad& load : training)
    if (!load.point_forces.empty()) training_centres.insert(load.point_forces[0].node);
  std::set<std::int32_t> constrained(scene.fixed_nodes.begin(), scene.fixed_nodes.end());
  constrained.insert(scene.prescribed_nodes.begin(), scene.prescribed_nodes.end());
  for (const TrainingLoad& load : held_out) {
    if (!load.point_forces.empty()) {
      EXPECT_FALSE(training_centres.count(load.point_forces[0].node)) << load.name;
    }
    for (const PointForce& f : load.point_forces) EXPECT_FALSE(constrained.count(f.node));
  }
  for (const TrainingLoad& load : training) {
    const double g = norm(load.gravity_m_s2);
    EXPECT_TRUE(std::abs(g - 9.81) < 1e-9 || std::abs(g - 0.5 * 9.81) < 1e-9) << load.name;
    if (load.name.starts_with("push")) {
      EXPECT_NEAR(norm(total_force(load)), options.probe_force_n, 1e-12);
    }
    if (load.name.starts_with("needle")) {
      EXPECT_NEAR(norm(total_force(load)), options.needle_force_n, 1e-12);
    }
    if (load.name.starts_with("diaphragm")) {
      EXPECT_NEAR(norm(load.prescribed_displacement_m), options.diaphragm_amplitude_m, 1e-12);
    }
  }
  for (const TrainingLoad& load : held_out) {
    if (load.name.starts_with("push")) {
      EXPECT_GE(norm(total_force(load)), 0.4 * options.probe_force_n - 1e-12);
      EXPECT_LE(norm(total_force(load)), 0.9 * options.probe_force_n + 1e-12);
    }
    if (load.name.starts_with("gravity x")) {
      EXPECT_NEAR(norm(load.gravity_m_s2), 0.75 * 9.81, 1e-9);  // between 0.5 and 1
    }
  }
}

TEST(TrainingLoads, DiaphragmIsTheTopPatchAwayFromFixedNodes) {
  const Column column;
  TissueScene scene = column.scene;
  scene.gravity_m_s2 = {0.0, 0.0, 9.81};  // "up" is -z, where the column is clamped (z = 0):
  const TissueScene with = with_diaphragm(column.mesh, scene, 0.006);
  // the patch centre is the lowest-z boundary node at least 12 mm from the clamp (z = 15 mm
  // on the 5 mm lattice), the patch its boundary nodes within 6 mm (z = 10, 15, 20 mm).
  ASSERT_GE(with.prescribed_nodes.size(), 3u);
  for (const std::int32_t n : with.prescribed_nodes) {
    const double z = column.mesh.nodes_m[static_cast<std::size_t>(n)][2];
    EXPECT_GE(z, 0.010 - 1e-9);
    EXPECT_LE(z, 0.020 + 1e-9);
  }
  scene.fixed_nodes.clear();  // nothing to keep away from: the patch is at the clamp's face
  for (const std::int32_t n : with_diaphragm(column.mesh, scene, 0.006).prescribed_nodes)
    EXPECT_LE(column.mesh.nodes_m[static_cast<std::size_t>(n)][2], 0.005 + 1e-9);
}

TEST(TrainingLoads, SmallLoadSolutionsMatchLinearStatics) {
  const Column column;
  TrainingLoad gravity{"gravity", column.scene.gravity_m_s2, {}, {}};
  const std::int32_t tip = testing::nodes_where(column.mesh, 2, kLengthM).front();
  TrainingLoad needle{"needle", column.scene.gravity_m_s2, {{tip, {0.0, 0.05, 0.0}}}, {}};
  const std::vector<TrainingLoad> loads{gravity, needle};
  StaticSolveOptions full_load_only;
  full_load_only.snapshot_fractions = {1.0};
  const auto solved = solve_static_loads(column.mesh, column.scene, loads, full_load_only);
  ASSERT_TRUE(solved.ok()) << solved.error().describe();
  ASSERT_EQ(solved.value().count, 2);
  const std::size_t rows = 3 * column.mesh.nodes_m.size();
  ASSERT_EQ(solved.value().displacements_m.size(), 2 * rows);

  for (int k = 0; k < 2; ++k) {
    // The same scene and loads as the training solve, in the format every solver takes.
    const StaticSolution reference =
        solve_linear_static(column.mesh, scene_for_load(column.scene, loads[k]), loads[k].inputs()).value();
    double largest_m = 0.0, largest_error_m = 0.0;
    for (std::size_t n = 0; n < column.mesh.nodes_m.size(); ++n) {
      const Point3 u{solved.value().displacements_m[k * rows + 3 * n],
                     solved.value().displacements_m[k * rows + 3 * n + 1],
                     solved.value().displacements_m[k * rows + 3 * n + 2]};
      largest_m = std::max(largest_m, norm(reference.displacement_m[n]));
      largest_error_m = std::max(largest_error_m, norm(u - reference.displacement_m[n]));
    }
    std::printf("%s: tip %.3f mm, largest difference from linear statics %.2e mm\n", loads[k].name.c_str(),
                1e3 * largest_m, 1e3 * largest_error_m);
    EXPECT_GT(largest_m, 1e-5);
    EXPECT_LT(largest_error_m, 0.01 * largest_m);  // geometric non-linearity is below 1 % here
  }
}

TEST(TrainingLoads, SnapshotsKeepSupportsAndPrescribedMotion) {
  Column column;
  column.scene.default_material = {2.0e4, 0.45, 1000.0};  // soft: centimetre displacements
  const TissueScene scene = with_diaphragm(column.mesh, column.scene, 0.006);
  TrainingLoadOptions options;
  options.gravity_scales = {1.0};
  options.gravity_tilts = 1;
  options.probe_pushes = 1;
  options.needle_forces = 1;
  options.diaphragm_moves = 1;
  options.diaphragm_amplitude_m = 0.004;
  const auto loads = make_training_loads(column.mesh, scene, options, LoadSet::training);
  const auto solved = solve_static_loads(column.mesh, scene, loads);
  ASSERT_TRUE(solved.ok()) << solved.error().describe();
  const std::size_t rows = 3 * column.mesh.nodes_m.size();
  ASSERT_EQ(solved.value().count, 2 * static_cast<int>(loads.size()));  // half and full load each
  for (int k = 0; k < solved.value().count; ++k) {
    const TrainingLoad& load = loads[static_cast<std::size_t>(k / 2)];
    const double fraction = k % 2 == 0 ? 0.5 : 1.0;
    const double* u = solved.value().displacements_m.data() + static_cast<std::size_t>(k) * rows;
    for (const std::int32_t n : scene.fixed_nodes)
      for (int c = 0; c < 3; ++c) EXPECT_EQ(u[3 * n + c], 0.0);
    for (const std::int32_t n : scene.prescribed_nodes)
      for (int c = 0; c < 3; ++c)
        EXPECT_NEAR(u[3 * n + c], fraction * load.prescribed_displacement_m[c], 1e-12) << load.name;
    double largest_m = 0.0;
    for (std::size_t i = 0; i < rows; ++i) largest_m = std::max(largest_m, std::abs(u[i]));
    EXPECT_GT(largest_m, fraction * 1e-3) << load.name;
  }
  std::printf("%d snapshots solved in %d quasi-static steps\n", solved.value().count, solved.value().total_steps);
}

TEST(TrainingLoads, NonConvergenceNamesTheLoad) {
  Column column;
  column.scene.default_material = {2.0e4, 0.45, 1000.0};
  const std::vector<TrainingLoad> loads{{"slow gravity", column.scene.gravity_m_s2, {}, {}}};
  StaticSolveOptions options;
  options.max_steps = 3;
  const auto solved = solve_static_loads(column.mesh, column.scene, loads, options);
  ASSERT_FALSE(solved.ok());
  EXPECT_EQ(solved.error().field, "slow gravity");
  EXPECT_NE(solved.error().message.find("did not converge"), std::string::npos);
}

}  // namespace
}  // namespace nav
