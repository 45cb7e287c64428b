// The reduced liver's escalation ladder as a scene declares it (issue 4, item 3), on the
// generated liver at 3 cm (309 tetrahedra): rung 0 is a POD basis of r = 4 with corotational
// cubature trained on ordinary loads, rung 1 its extension (extend_basis) to r = 8 trained on
// 3 times the needle and diaphragm loads, as `navtool reduce --extend ... --load-scale 3` makes
// them. build_station builds the ladder alone (no separate reduced model), lists each rung in
// the footprint, places the ladder builder's errors at their scene keys, and the built ladder,
// stepped under a diaphragm displacement 2.5 times the training's, escalates to rung 1 when
// the scene allows it and only raises the indicator's flag when it does not.
// `navstation --check` prints the ladder.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "nav/mesher/embedded_liver.hpp"
#include "nav/reduced/reduced_artifact.hpp"
#include "nav/reduced/reduced_ladder_basis.hpp"
#include "nav/reduced/reduction.hpp"
#include "nav/reduced/training_loads.hpp"
#include "nav/station/station_build.hpp"
#include "scene_build.hpp"
#include "scene_text.hpp"
#include "support/run_command.hpp"

namespace nav::station {
namespace {

using testing::build_text;
using testing::demo_text;
using testing::edited;
using testing::example_scene_path;
using testing::line_of;

constexpr double kElementSizeM = 0.03;
constexpr double kWideScale = 3.0;  ///< the upper rung's training: 3 times the needle and diaphragm loads

/// Snapshots of a short training set (gravity, one tilt, two needles, three diaphragm moves),
/// its needle forces and diaphragm displacements times `scale`.
Snapshots training(const TetMesh& mesh, const TissueScene& scene, double scale) {
  TrainingLoadOptions options;
  options.gravity_tilts = 1;
  options.probe_pushes = 0;
  options.needle_forces = 2;
  options.diaphragm_moves = 3;
  options.needle_force_n *= scale;
  options.diaphragm_amplitude_m *= scale;
  auto snapshots = solve_static_loads(mesh, scene, make_training_loads(mesh, scene, options, LoadSet::training));
  EXPECT_TRUE(snapshots.ok()) << snapshots.error().describe();
  return std::move(snapshots).value();
}

/// The two artifacts of the ladder, written once for the program.
struct Artifacts {
  std::string lower = testing::temporary_path("station_ladder_lower.navrb");
  std::string upper = testing::temporary_path("station_ladder_upper.navrb");

  Artifacts() {
    const TetMesh mesh = make_embedded_liver(kElementSizeM).mesh;
    const TissueScene scene = liver_reduction_scene(mesh);
    const TissueSolverOptions solver = reduction_solver_options(ReducedForceKind::corotational_cubature);
    ReductionOptions options;
    options.basis_size = 4;
    options.max_cubature_samples = 30;
    const Snapshots base = training(mesh, scene, 1.0);
    auto small = make_pod_basis(mesh, scene, solver, options, base.displacements_m, base.count);
    EXPECT_TRUE(small.ok()) << small.error().describe();
    EXPECT_TRUE(
        add_force_reduction(mesh, scene, solver, options, base.displacements_m, base.count, small.value()).ok());
    const Snapshots wide = training(mesh, scene, kWideScale);
    options.basis_size = 8;
    auto big = extend_basis(mesh, scene, solver, small.value(), 8, wide.displacements_m, wide.count);
    EXPECT_TRUE(big.ok()) << big.error().describe();
    EXPECT_TRUE(add_force_reduction(mesh, scene, solver, options, wide.displacements_m, wide.count, big.value()).ok());
    EXPECT_TRUE(save_reduced_basis(lower, small.value()).ok());
    EXPECT_TRUE(save_reduced_basis(upper, big.value()).ok());
  }
};

const Artifacts& artifacts() {
  static const Artifacts instance;
  return instance;
}

/// The demo scene with the generated liver at kElementSizeM, reduced on `artifact`, and `escalation`
/// (lines of the block under `model:`); the demo's URDF by its absolute path, so that the text
/// may be written anywhere.
std::string ladder_scene(const std::string& artifact, const std::string& escalation) {
  const std::string& demo = demo_text();
  const std::string urdf =
      (std::filesystem::path(example_scene_path("demo.yaml")).parent_path() / "../../../calibration/urdf/station.urdf")
          .lexically_normal()
          .string();
  const std::string liver = "liver:\n  mesh: {source: generated, element_size_m: " + std::to_string(kElementSizeM) +
                            "}\n  model:\n    rung: reduced\n    artifact: " + artifact + "\n" + escalation;
  const std::string text = demo.substr(0, demo.find("liver:\n")) + liver + demo.substr(demo.find("\nneedle:") + 1);
  return edited(text, "urdf: ../../../calibration/urdf/station.urdf", "urdf: " + urdf);
}

std::string two_rungs(const std::string& options = "") {
  return "    escalation:\n      rungs: [" + artifacts().upper + "]\n" + options;
}

const FootprintLine* line_named(const MemoryFootprint& footprint, const std::string& part) {
  for (const FootprintLine& line : footprint.lines)
    if (line.part == part) return &line;
  return nullptr;
}

TEST(StationLadder, BuildsTheDeclaredRungsAloneAndListsThemInTheFootprint) {
  const auto built = build_text(ladder_scene(artifacts().lower, two_rungs()));
  ASSERT_TRUE(built.ok()) << built.error().describe();
  const LiverModels& liver = built.value().models.liver;
  ASSERT_TRUE(liver.ladder.has_value() && liver.ladder_data.has_value());
  EXPECT_FALSE(liver.reduced.has_value());
  EXPECT_FALSE(liver.full.has_value());
  const ReducedLadderModel& ladder = *liver.ladder;
  EXPECT_EQ(ladder.rung_count(), 2);
  EXPECT_FALSE(ladder.has_full_order());
  EXPECT_EQ(ladder.reduced_rung(0).basis_size(), 4);
  EXPECT_EQ(ladder.reduced_rung(1).basis_size(), 8);
  EXPECT_LT(ladder.transfer_loss(0), 1e-9);  // the upper basis starts with the lower's columns
  EXPECT_TRUE(ladder.options().escalation_allowed);
  EXPECT_EQ(liver.ladder_data->active_rung, 0);
  // The rungs' own reports in the footprint, and the rest adds up.
  const MemoryFootprint& f = built.value().footprint;
  for (int k = 0; k < 2; ++k) {
    const FootprintLine* tables = line_named(f, "rung " + std::to_string(k) + " reduced tables");
    const FootprintLine* arena = line_named(f, "rung " + std::to_string(k) + " data arena");
    ASSERT_TRUE(tables != nullptr && arena != nullptr) << format_footprint(f);
    EXPECT_EQ(tables->bytes, ladder.reduced_rung(k).memory_bytes());
    EXPECT_GE(arena->bytes,
              static_cast<std::int64_t>(liver.ladder_data->reduced[static_cast<std::size_t>(k)].arena.used_bytes()));
  }
  const FootprintLine* transfers = line_named(f, "ladder transfers");
  ASSERT_NE(transfers, nullptr);
  EXPECT_EQ(transfers->bytes, 4 * 8 * 8);  // one 8 x 4 operator of doubles
  EXPECT_EQ(line_named(f, "reduced tables"), nullptr);
  EXPECT_EQ(f.total_bytes(), f.model_bytes("liver") + f.model_bytes("needle"));

  // With the full order on top: a third rung, its tables estimated.
  const auto topped = build_text(ladder_scene(artifacts().lower, two_rungs("      full_order_on_top: true\n")));
  ASSERT_TRUE(topped.ok()) << topped.error().describe();
  const ReducedLadderModel& three = *topped.value().models.liver.ladder;
  EXPECT_EQ(three.rung_count(), 3);
  ASSERT_TRUE(three.has_full_order());
  EXPECT_EQ(three.full_order().tet_count(), static_cast<std::int64_t>(topped.value().models.liver.mesh.tets.size()));
  const FootprintLine* full = line_named(topped.value().footprint, "rung 2 full-order tables");
  ASSERT_NE(full, nullptr);
  EXPECT_TRUE(full->estimated);
  EXPECT_GT(topped.value().footprint.model_bytes("liver"), f.model_bytes("liver") + full->bytes);
}

TEST(StationLadder, LadderErrorsNameTheirSceneKeyAndLine) {
  // Rungs out of order: the upper artifact at the bottom.
  const std::string swapped =
      ladder_scene(artifacts().upper, "    escalation:\n      rungs: [" + artifacts().lower + "]\n");
  const auto refused = build_text(swapped);
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.error().file, example_scene_path("demo.yaml"));
  EXPECT_EQ(refused.error().field, "liver.model.escalation.rungs[0] (basis.basis_size)");
  EXPECT_EQ(refused.error().line, line_of(swapped, "      rungs:"));
  EXPECT_NE(refused.error().message.find("grow strictly"), std::string::npos) << refused.error().describe();
  // A missing artifact on its own line of the list.
  const std::string missing =
      ladder_scene(artifacts().lower, "    escalation:\n      rungs:\n        - " + artifacts().upper +
                                          "\n        - /no/such/rung.navrb\n");
  const auto absent = build_text(missing);
  ASSERT_FALSE(absent.ok());
  EXPECT_EQ(absent.error().field, "liver.model.escalation.rungs[1]");
  EXPECT_EQ(absent.error().line, line_of(missing, "        - /no/such"));
  EXPECT_NE(absent.error().message.find("/no/such/rung.navrb"), std::string::npos) << absent.error().describe();
  // The full order on top takes the rungs' integrator: quasi-static reduced rungs get the
  // quasi-static full order (make_reduced_ladder_model refuses any other pairing).
  const auto quasi_static = build_text(
      ladder_scene(artifacts().lower, "    integrator: quasi_static\n" + two_rungs("      full_order_on_top: true\n")));
  ASSERT_TRUE(quasi_static.ok()) << quasi_static.error().describe();
}

/// Steps the built ladder for 50 tissue steps under a diaphragm displacement along the
/// training's gravity, ramped over 25 steps to 4 times the training amplitude and held (the
/// station's liver has no gravity, whose sag the training's envelope holds too).
void push_beyond_training(const LiverModels& liver, ReducedLadderData& data) {
  const TrainingLoadOptions defaults;
  const Point3 g = liver_reduction_scene(liver.mesh).gravity_m_s2;
  const double g_norm = std::sqrt(g[0] * g[0] + g[1] * g[1] + g[2] * g[2]);
  for (int i = 0; i < 50; ++i) {
    TissueInputs inputs;
    const double amplitude_m = 4.0 * defaults.diaphragm_amplitude_m * std::min(1.0, (i + 1) / 25.0);
    for (int k = 0; k < 3; ++k)
      inputs.prescribed_displacement_m[static_cast<std::size_t>(k)] =
          amplitude_m * g[static_cast<std::size_t>(k)] / g_norm;
    step(*liver.ladder, data, inputs);
  }
}

bool all_finite(const ReducedLadderModel& ladder, const ReducedLadderData& data) {
  std::vector<double> u(3 * static_cast<std::size_t>(ladder.node_count()));
  reconstruct_all_displacements_m(ladder, data, u);
  for (double value : u)
    if (!std::isfinite(value)) return false;
  return true;
}

TEST(StationLadder, BeyondTrainingTheBuiltLadderEscalatesWhenAllowedAndOnlyFlagsWhenNot) {
  auto allowed = build_text(ladder_scene(artifacts().lower, two_rungs("      allowed: true\n")));
  ASSERT_TRUE(allowed.ok()) << allowed.error().describe();
  LiverModels& up = allowed.value().models.liver;
  push_beyond_training(up, *up.ladder_data);
  EXPECT_EQ(up.ladder_data->active_rung, 1);
  EXPECT_GE(up.ladder_data->escalations, 1);
  EXPECT_TRUE(up.ladder_data->health.has(HealthFlag::reduced_escalated)) << up.ladder_data->health.bits();
  EXPECT_TRUE(up.ladder_data->health.has(HealthFlag::reduced_out_of_envelope));
  EXPECT_TRUE(all_finite(*up.ladder, *up.ladder_data));

  auto flag_only = build_text(ladder_scene(artifacts().lower, two_rungs("      allowed: false\n")));
  ASSERT_TRUE(flag_only.ok()) << flag_only.error().describe();
  LiverModels& stay = flag_only.value().models.liver;
  EXPECT_FALSE(stay.ladder->options().escalation_allowed);
  push_beyond_training(stay, *stay.ladder_data);
  EXPECT_EQ(stay.ladder_data->active_rung, 0);
  EXPECT_EQ(stay.ladder_data->escalations, 0);
  EXPECT_TRUE(stay.ladder_data->health.has(HealthFlag::reduced_out_of_envelope)) << stay.ladder_data->health.bits();
  EXPECT_FALSE(stay.ladder_data->health.has(HealthFlag::reduced_escalated));
  EXPECT_GT(stay.ladder_data->report.envelope_ratio, stay.ladder->reduced_rung(0).options().envelope_factor);
  EXPECT_TRUE(all_finite(*stay.ladder, *stay.ladder_data));
}

TEST(StationLadder, NavstationCheckPrintsTheLadder) {
  const std::string path = testing::temporary_path("station_ladder_scene.yaml");
  {
    std::ofstream file(path);
    file << ladder_scene(artifacts().lower, two_rungs("      escalate_after_steps: 2\n"));
  }
  const auto run = testing::run_command(testing::executable_path("navstation") + " --scene " + path + " --check 2>&1");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  for (const char* expected :
       {"liver escalation ladder: 2 rungs; escalation allowed after 2 flagged step(s); never steps down",
        "rung 0  reduced r = 4, ", "rung 1  reduced r = 8, ", "transfer loss to rung 1", "rung 1 reduced tables",
        "ladder transfers"})
    EXPECT_NE(run.output.find(expected), std::string::npos) << expected << "\n" << run.output;
}

}  // namespace
}  // namespace nav::station
