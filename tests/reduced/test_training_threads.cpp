// The training's full-order solves, several loads at once: the snapshots are those of one
// thread bit for bit, and a load that does not solve names itself without costing the others.
#include <gtest/gtest.h>

#include "nav/reduced/training_loads.hpp"
#include "tissue/tissue_test_support.hpp"

namespace nav {
namespace {

/// A soft 2 x 2 x 6 cm column clamped at z = 0 under a diaphragm patch: centimetre displacements.
struct SoftColumn {
  TetMesh mesh = testing::box_mesh({0.02, 0.02, 0.06}, 0.005);
  TissueScene scene;
  SoftColumn() {
    scene.default_material = {2.0e4, 0.45, 1000.0};
    scene.gravity_m_s2 = {-9.81, 0.0, 0.0};
    scene.fixed_nodes = testing::nodes_where(mesh, 2, 0.0);
    scene = with_diaphragm(mesh, scene, 0.006);
  }
};

TEST(TrainingThreads, SnapshotsOnThreeThreadsAreThoseOfOneBitForBit) {
  const SoftColumn column;
  TrainingLoadOptions load_options;
  load_options.gravity_scales = {0.5, 1.0};
  load_options.gravity_tilts = 1;
  load_options.probe_pushes = 2;
  load_options.needle_forces = 2;
  load_options.diaphragm_moves = 1;
  load_options.diaphragm_amplitude_m = 0.004;
  const auto loads = make_training_loads(column.mesh, column.scene, load_options, LoadSet::training);
  ASSERT_GE(loads.size(), 5U);
  StaticSolveOptions one_thread, three_threads;
  three_threads.threads = 3;
  const auto alone = solve_static_loads(column.mesh, column.scene, loads, one_thread);
  const auto together = solve_static_loads(column.mesh, column.scene, loads, three_threads);
  ASSERT_TRUE(alone.ok()) << alone.error().describe();
  ASSERT_TRUE(together.ok()) << together.error().describe();
  EXPECT_EQ(together.value().count, 2 * static_cast<int>(loads.size()));
  EXPECT_EQ(together.value().count, alone.value().count);
  EXPECT_EQ(together.value().total_steps, alone.value().total_steps);
  EXPECT_TRUE(together.value().displacements_m == alone.value().displacements_m);  // bitwise: no tolerance
}

TEST(TrainingThreads, ALoadThatDoesNotSolveNamesItselfAndTheOthersSolve) {
  const SoftColumn column;
  const std::vector<TrainingLoad> loads{{"no load", {0.0, 0.0, 0.0}, {}, {}},
                                        {"slow gravity", column.scene.gravity_m_s2, {}, {}},
                                        {"no load again", {0.0, 0.0, 0.0}, {}, {}}};
  StaticSolveOptions options;
  options.max_steps = 3;  // too few for gravity after its ramp, plenty for no load
  options.threads = 2;
  const auto each = solve_each_static_load(column.mesh, column.scene, loads, options);
  ASSERT_EQ(each.size(), loads.size());
  ASSERT_TRUE(each[0].ok()) << each[0].error().describe();
  ASSERT_TRUE(each[2].ok()) << each[2].error().describe();
  EXPECT_EQ(each[0].value().count, 2);
  EXPECT_EQ(each[0].value().displacements_m.size(), 2 * 3 * column.mesh.nodes_m.size());
  ASSERT_FALSE(each[1].ok());
  EXPECT_EQ(each[1].error().field, "slow gravity");
  EXPECT_NE(each[1].error().message.find("did not converge"), std::string::npos);
  const auto all = solve_static_loads(column.mesh, column.scene, loads, options);
  ASSERT_FALSE(all.ok());
  EXPECT_EQ(all.error().field, "slow gravity");
}

}  // namespace
}  // namespace nav
