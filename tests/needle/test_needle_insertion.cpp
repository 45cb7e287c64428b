// Needle-tissue interaction as constraints, stand-alone tissue (local compliance): plate
// puncture, an insertion-retraction profile, shaft friction against inserted length,
// re-insertion without cutting, a stiff inclusion, Signorini and Coulomb after correction,
// pool exhaustion, the bevel switch, allocation-free and bitwise repeatable steps.
#include <gtest/gtest.h>

#include <algorithm>

#include "needle_insertion_support.hpp"
#include "support/allocation_guard.hpp"

namespace nav {
namespace {

using testing::drive_to;
using testing::facing_layer;
using testing::Sample;

constexpr double kSurfaceX = 0.155;  // the needle's tip starts at x = 0.15

NeedleTissueScene plate_scene(double friction_n_m) {
  NeedleTissueScene scene;
  scene.layers = {facing_layer(kSurfaceX, 1.0, 0.3, friction_n_m)};
  return scene;
}

TEST(NeedleInsertion, PlatePunctureForceRisesToFpThenDropsToTheCuttingPlateau) {
  const NeedleTissueModel model = make_needle_tissue_model(NeedleParameters{}, plate_scene(0.0)).value();
  NeedleTissueData data = make_needle_tissue_data(model, {}).value();
  std::vector<Sample> record;
  drive_to(model, data, 0.02, testing::kInsertionStepM, record);
  ASSERT_EQ(data.report.punctures, 1);
  const auto peak = std::max_element(record.begin(), record.end(), [](const Sample& a, const Sample& b) {
    return a.forces.total_n < b.forces.total_n;
  });
  // Before the puncture the force is the tissue's stiffness times the depth pushed in.
  const double stiffness_n_m = 1.0 / model.scene.point_compliance_m_per_n;
  const Sample& halfway =
      *std::find_if(record.begin(), record.end(), [](const Sample& s) { return s.forces.total_n > 0.5; });
  EXPECT_NEAR(halfway.forces.stiffness_n / (stiffness_n_m * halfway.depth_m), 1.0, 0.05);
  EXPECT_NEAR(peak->forces.total_n, 1.0, 0.02);  // f_p
  std::printf("plate: peak %.4f N at depth %.2f mm, plateau %.4f N\n", peak->forces.total_n, 1e3 * peak->depth_m,
              record.back().forces.total_n);
  // After it: the cutting plateau (no friction in this scene).
  for (auto s = record.end() - 200; s != record.end(); ++s) {
    EXPECT_NEAR(s->forces.cutting_n, 0.3, 0.006);
    EXPECT_NEAR(s->forces.total_n, 0.3, 0.006);
    EXPECT_LT(s->residual_m, 1e-6);
  }
}

TEST(NeedleInsertion, InsertionRetractionProfileShowsItsPhases) {
  const NeedleTissueModel model = make_needle_tissue_model(NeedleParameters{}, plate_scene(20.0)).value();
  NeedleTissueData data = make_needle_tissue_data(model, {}).value();
  std::vector<Sample> insert, hold, retract, reinsert, deeper, out;
  drive_to(model, data, 0.035, testing::kInsertionStepM, insert);  // 1: puncture, 2: friction growing with depth
  const double front_depth_m = data.report.tip_depth_m;
  for (int k = 0; k < 200; ++k) drive_to(model, data, 0.035, testing::kInsertionStepM, hold);  // 3: hold
  drive_to(model, data, 0.025, testing::kInsertionStepM, retract);                             // 4: partial retraction
  drive_to(model, data, 0.035, testing::kInsertionStepM, reinsert);  // 5: re-insertion along the path
  drive_to(model, data, 0.040, testing::kInsertionStepM, deeper);    // ... and beyond the old front
  drive_to(model, data, -0.01, testing::kInsertionStepM, out);       // 6: full retraction
  // 2: friction grows with the inserted length: f_len per unit length, sampled every
  // path spacing (so within one spacing's worth of friction of f_len * depth).
  for (double depth_m : {0.012, 0.018, 0.024, 0.029}) {
    const Sample& s = *std::find_if(insert.begin(), insert.end(), [&](const Sample& x) { return x.depth_m > depth_m; });
    std::printf("friction at %.0f mm: %.3f N\n", 1e3 * depth_m, s.forces.friction_n);
    EXPECT_NEAR(s.forces.friction_n, 20.0 * depth_m, 20.0 * model.scene.path_spacing_m);
    EXPECT_GT(s.forces.friction_n, 0.0);
  }
  EXPECT_GT(insert.back().forces.friction_n, std::find_if(insert.begin(), insert.end(), [](const Sample& x) {
                                               return x.depth_m > 0.012;
                                             })->forces.friction_n);
  // The tissue ahead of the tip, compressed by the cutting force, unloads over
  // f_cut * compliance (0.6 mm) when the tip backs off; beyond twice that nothing touches it.
  const double unloaded_m = 2.0 * 0.3 * model.scene.point_compliance_m_per_n;
  // 4: retraction: the force changes sign (friction resists withdrawal) and nothing is cut.
  EXPECT_LT(retract.back().forces.total_n, 0.0);
  for (const Sample& s : retract) {
    if (s.depth_m < front_depth_m - unloaded_m) {
      EXPECT_EQ(s.forces.cutting_n, 0.0);
    }
  }
  // 5: re-insertion along the existing path meets friction but no cutting force.
  for (const Sample& s : reinsert) {
    if (s.depth_m < front_depth_m - unloaded_m) {
      EXPECT_EQ(s.forces.cutting_n, 0.0);
    }
  }
  EXPECT_GT(reinsert.back().forces.friction_n, 0.0);
  // ... and cutting again once past the old front.
  // (the newest path point, at the tip, may share the load as friction)
  EXPECT_GT(deeper.back().forces.cutting_n, 0.25);
  EXPECT_LE(deeper.back().forces.cutting_n, 0.3 + 1e-9);
  // 6: full retraction: friction falls as path constraints leave the needle, to nothing.
  const auto in_tissue = std::find_if(out.begin(), out.end(), [](const Sample& s) { return s.depth_m < 0.02; });
  const auto shallow = std::find_if(out.begin(), out.end(), [](const Sample& s) { return s.depth_m < 0.01; });
  EXPECT_LT(std::abs(shallow->forces.friction_n), std::abs(in_tissue->forces.friction_n));
  EXPECT_EQ(out.back().path_points, 0);
  EXPECT_EQ(out.back().forces.total_n, 0.0);
  EXPECT_EQ(data.report.punctures, 1);  // the hole is used again
}

TEST(NeedleInsertion, SignoriniAndCoulombHoldAfterCorrection) {
  NeedleTissueScene scene = plate_scene(20.0);
  scene.layers.push_back(facing_layer(kSurfaceX + 0.02, 2.0, 0.5, 30.0));
  const NeedleTissueModel model = make_needle_tissue_model(NeedleParameters{}, scene).value();
  NeedleTissueData data = make_needle_tissue_data(model, {}).value();
  NeedleTissueInputs inputs;
  double worst_m = 0.0;
  int rows_seen = 0;
  for (int s = 1; s <= 2500; ++s) {
    // Insert with a lateral wobble of the base, so that lateral and axial forces both act.
    const double x = std::min(0.04, testing::kInsertionStepM * s);
    inputs.needle.base.position_m = {x, 2e-3 * std::sin(2e-3 * s), 0.0};
    step(model, data, inputs);
    const double v = testing::violation_after_correction(model, data);
    worst_m = std::max(worst_m, v);
    rows_seen = std::max(rows_seen, data.row_count);
  }
  std::printf("largest law violation after correction: %.2e m over %d rows at most\n", worst_m, rows_seen);
  EXPECT_GE(rows_seen, 12);
  EXPECT_LT(worst_m, 1e-5);  // 10 um after 30 sweeps
  EXPECT_FALSE(data.health.has(HealthFlag::solver_not_converged));
}

TEST(NeedleInsertion, StiffInclusionDeflectsTheNeedleUntilItsOwnPunctureForce) {
  NeedleTissueScene scene;
  scene.layers = {facing_layer(kSurfaceX, 1.0, 0.3, 5.0)};
  TissueLayer inclusion = facing_layer(kSurfaceX + 0.015, 3.0, 1.0, 5.0);
  inclusion.outward_normal = {-std::cos(0.5), std::sin(0.5), 0.0};  // a slanted stiff surface
  inclusion.surface_friction_coefficient = 0.05;
  scene.layers.push_back(inclusion);
  const auto lateral_at_inclusion_puncture = [&](double youngs_modulus_pa) {
    NeedleParameters needle;
    needle.youngs_modulus_pa = youngs_modulus_pa;
    const NeedleTissueModel model = make_needle_tissue_model(needle, scene).value();
    NeedleTissueData data = make_needle_tissue_data(model, {}).value();
    NeedleTissueInputs inputs;
    double largest_normal_n = 0.0, lateral_m = 0.0;
    for (int s = 1; s <= 3000 && data.report.punctures < 2; ++s) {
      inputs.needle.base.position_m = {testing::kInsertionStepM * s, 0.0, 0.0};
      lateral_m = needle_tip_m(data.needle).y();
      step(model, data, inputs);
      largest_normal_n = std::max(largest_normal_n, data.report.contact_force_n);
    }
    EXPECT_EQ(data.report.punctures, 2);
    EXPECT_NEAR(largest_normal_n, 3.0, 1e-9);  // pushed up to the inclusion's own f_p, no further
    return lateral_m;
  };
  const double steel = lateral_at_inclusion_puncture(200e9), softer = lateral_at_inclusion_puncture(50e9);
  std::printf("tip deflected %.3f mm (steel) and %.3f mm (E/4) before the inclusion gave way\n", 1e3 * steel,
              1e3 * softer);
  EXPECT_GT(std::abs(steel), 1e-4);
  EXPECT_GT(std::abs(softer), std::abs(steel));  // a more flexible needle deflects more
}

TEST(NeedleInsertion, FullPathPoolLosesTheNewestPointsAndFlagsIt) {
  NeedleTissueScene scene = plate_scene(20.0);
  scene.max_path_points = 3;
  const NeedleTissueModel model = make_needle_tissue_model(NeedleParameters{}, scene).value();
  NeedleTissueData data = make_needle_tissue_data(model, {}).value();
  std::vector<Sample> record;
  drive_to(model, data, 0.06, testing::kInsertionStepM, record);
  EXPECT_TRUE(data.health.has(HealthFlag::pool_full));
  EXPECT_GT(data.report.lost_path_points, 0);
  EXPECT_EQ(data.report.active_path_points, 3);
  EXPECT_FALSE(data.health.has(HealthFlag::non_finite_state));
  // The loss is predictable: the friction is that of the three points it kept.
  EXPECT_NEAR(record.back().forces.friction_n, 3 * 20.0 * scene.path_spacing_m, 1e-3);
}

TEST(NeedleInsertion, BevelSteeringIsASwitchAndCurvesThePathTowardsTheBevel) {
  const auto lateral_offsets = [](bool bevel) {
    NeedleTissueScene scene = plate_scene(5.0);
    scene.bevel_steering = bevel;
    const NeedleTissueModel model = make_needle_tissue_model(NeedleParameters{}, scene).value();
    NeedleTissueData data = make_needle_tissue_data(model, {}).value();
    std::vector<Sample> record;
    drive_to(model, data, 0.04, testing::kInsertionStepM, record);
    // Tip offsets at 5, 20 and 35 mm deep.
    std::vector<double> offsets;
    for (double depth_m : {0.005, 0.02, 0.0349})
      offsets.push_back(
          std::find_if(record.begin(), record.end(), [&](const Sample& s) { return s.depth_m > depth_m; })->tip_m.y());
    return offsets;
  };
  const std::vector<double> straight = lateral_offsets(false), steered = lateral_offsets(true);
  std::printf("tip lateral offset at 5 / 20 / 35 mm: %.3f / %.3f / %.3f mm with bevel, %.1e without\n",
              1e3 * steered[0], 1e3 * steered[1], 1e3 * steered[2], straight[2]);
  for (double y : straight) EXPECT_EQ(y, 0.0);
  // Towards the bevel's open side (+y of the tip frame), and curving: the second 15 mm add
  // more offset than the first.
  EXPECT_GT(steered[0], 0.0);
  EXPECT_GT(steered[2] - steered[1], steered[1] - steered[0]);
  EXPECT_GT(steered[1] - steered[0], 0.0);
}

TEST(NeedleInsertion, StepsAllocateNothingAndRepeatBitwise) {
  NeedleTissueScene scene = plate_scene(20.0);
  scene.layers.push_back(facing_layer(kSurfaceX + 0.02, 2.0, 0.5, 30.0));
  const NeedleTissueModel model = make_needle_tissue_model(NeedleParameters{}, scene).value();
  std::uint64_t hashes[2] = {0, 0};
  for (std::uint64_t& hash : hashes) {
    NeedleTissueData data = make_needle_tissue_data(model, {}).value();
    NeedleTissueInputs inputs;
    testing::AllocationGuard guard;
    for (int s = 1; s <= 2000; ++s) {
      inputs.needle.base.position_m = {testing::kInsertionStepM * s, 1e-3 * std::sin(3e-3 * s), 0.0};
      step(model, data, inputs);
    }
    EXPECT_EQ(guard.allocations(), 0u);
    hash = testing::bits_hash({data.needle.positions_m, data.needle.rotations_wxyz, data.slot_forces});
  }
  EXPECT_EQ(hashes[0], hashes[1]);
}

TEST(NeedleInsertion, BadPoseLeavesTheInteractionUntouched) {
  const NeedleTissueModel model = make_needle_tissue_model(NeedleParameters{}, plate_scene(20.0)).value();
  NeedleTissueData data = make_needle_tissue_data(model, {}).value();
  std::vector<Sample> record;
  drive_to(model, data, 0.02, testing::kInsertionStepM, record);
  const std::uint64_t before = testing::bits_hash({data.needle.positions_m, data.slot_forces});
  NeedleTissueInputs inputs;
  inputs.needle.base.position_m = {0.02 + 0.05, 0.0, 0.0};  // a 5 cm jump
  step(model, data, inputs);
  EXPECT_TRUE(data.health.has(HealthFlag::bad_sample));
  EXPECT_EQ(testing::bits_hash({data.needle.positions_m, data.slot_forces}), before);
}

TEST(NeedleInsertion, SceneOutOfRangeIsRefusedNamingTheField) {
  NeedleTissueScene scene = plate_scene(20.0);
  scene.layers[0].puncture_force_n = -1.0;
  EXPECT_EQ(make_needle_tissue_model(NeedleParameters{}, scene).error().field, "scene.layers[0].puncture_force_n");
  scene = plate_scene(20.0);
  scene.layers[0].outward_normal = {0.0, 0.0, 2.0};
  EXPECT_EQ(make_needle_tissue_model(NeedleParameters{}, scene).error().field, "scene.layers[0].outward_normal");
  scene = plate_scene(20.0);
  scene.gauss_seidel_sweeps = 0;
  EXPECT_EQ(make_needle_tissue_model(NeedleParameters{}, scene).error().field, "scene.gauss_seidel_sweeps");
}

}  // namespace
}  // namespace nav
