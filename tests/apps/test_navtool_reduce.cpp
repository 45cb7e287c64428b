// navtool reduce, run as a process on the liver at about 1000 (and 500) tetrahedra: a POD artifact with
// its captured energy per mode and cubature, a vibration-mode artifact with its frequencies,
// both loadable for that mesh (and only that mesh); an upper rung (--extend) that keeps the
// lower rung's columns bit for bit and makes a ladder with no transfer loss, its widened
// training leaving out (and naming) the loads the full order cannot solve; exit code 2 with a
// clear message for bad arguments, a missing mesh file and a lower artifact that does not fit.
// And the shipped real-liver scene's two artifacts, made as its header says (the set-up of
// the live station's case that runs that scene: a ctest fixture, tests/CMakeLists.txt).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <string>
#include <vector>

#include "nav/reduced/reduced_artifact.hpp"
#include "nav/reduced/reduced_ladder.hpp"
#include "nav/reduced/training_loads.hpp"
#include "nav/tissue/liver_scenes.hpp"
#include "station/scene_text.hpp"
#include "support/run_command.hpp"
#include "support/test_data.hpp"

namespace {

nav::testing::CommandRun run_navtool(const std::string& arguments, const std::string& streams = "2>&1") {
  return nav::testing::run_command(nav::testing::executable_path("navtool") + " " + arguments + " " + streams);
}

/// The numbers of the JSON array that follows `"key": [` in `text`.
std::vector<double> json_array(const std::string& text, const std::string& key) {
  std::vector<double> values;
  std::size_t at = text.find("\"" + key + "\": [");
  if (at == std::string::npos) return values;
  at = text.find('[', at) + 1;
  const std::size_t end = text.find(']', at);
  while (at < end) {
    char* next = nullptr;
    values.push_back(std::strtod(text.c_str() + at, &next));
    at = static_cast<std::size_t>(next - text.c_str());
    while (at < end && (text[at] == ',' || text[at] == ' ')) ++at;
  }
  return values;
}

#define LIVER_OR_SKIP(dir)                                         \
  const std::string dir = nav::testing::shared_data_path("liver"); \
  NAV_REQUIRE_SHARED_DATA(dir + "/liver-smoothUV.obj")

TEST(NavtoolReduce, PodArtifactReportsEnergyAndCubatureAndLoadsForItsMeshOnly) {
  LIVER_OR_SKIP(dir);
  const std::string out = nav::testing::temporary_path("reduce_pod.navrb");
  const auto run =
      run_navtool("reduce --liver-dir " + dir +
                      " --tets 1000 --method pod --r 12 --force corotational --samples 40 --out " + out + " --json",
                  "2>/dev/null");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const std::vector<double> energy = json_array(run.output, "captured_energy_fraction");
  ASSERT_EQ(energy.size(), 12u) << run.output;
  for (std::size_t k = 1; k < energy.size(); ++k) EXPECT_GE(energy[k], energy[k - 1]);
  EXPECT_GT(energy.front(), 0.0);
  EXPECT_LE(energy.back(), 1.0 + 1e-12);
  EXPECT_GT(energy.back(), 0.99);  // 12 modes of 19 smooth training fields
  const std::size_t samples_at = run.output.find("\"cubature_samples\": ");
  ASSERT_NE(samples_at, std::string::npos);
  const int samples = std::atoi(run.output.c_str() + samples_at + 20);
  EXPECT_GT(samples, 0);
  EXPECT_LE(samples, 40);

  const nav::TetMesh mesh = nav::load_liver_mesh(dir, 1000).value();
  const auto basis = nav::load_reduced_basis(out, &mesh);
  ASSERT_TRUE(basis.ok()) << basis.error().describe();
  EXPECT_EQ(basis.value().basis_size, 12);
  EXPECT_EQ(basis.value().source, nav::ReducedBasisSource::pod);
  EXPECT_EQ(basis.value().force_kind, nav::ReducedForceKind::corotational_cubature);
  EXPECT_EQ(static_cast<int>(basis.value().sample_tets.size()), samples);
  EXPECT_FALSE(basis.value().diaphragm_lift.empty());  // the reduction scene has a diaphragm
  const nav::TetMesh other = nav::load_liver_mesh(dir, 5000).value();
  const auto refused = nav::load_reduced_basis(out, &other);
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.error().describe().find("belongs to another mesh"), std::string::npos);
}

TEST(NavtoolReduce, VibrationModesReportAscendingFrequencies) {
  LIVER_OR_SKIP(dir);
  const std::string out = nav::testing::temporary_path("reduce_modes.navrb");
  const auto table =
      run_navtool("reduce --liver-dir " + dir + " --tets 1000 --method modes --r 6 --force linear --out " + out);
  ASSERT_EQ(table.exit_code, 0) << table.output;
  EXPECT_NE(table.output.find("frequency (Hz"), std::string::npos) << table.output;
  EXPECT_NE(table.output.find("written: " + out), std::string::npos);
  const auto run = run_navtool(
      "reduce --liver-dir " + dir + " --tets 1000 --method modes --r 6 --force linear --out " + out + " --json",
      "2>/dev/null");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const std::vector<double> hz = json_array(run.output, "mode_frequency_hz");
  ASSERT_EQ(hz.size(), 6u) << run.output;
  EXPECT_GT(hz.front(), 0.0);
  for (std::size_t k = 1; k < hz.size(); ++k) EXPECT_GE(hz[k], hz[k - 1]);
  const auto basis = nav::load_reduced_basis(out, nullptr);
  ASSERT_TRUE(basis.ok()) << basis.error().describe();
  EXPECT_EQ(basis.value().source, nav::ReducedBasisSource::linear_modes);
}

TEST(NavtoolReduce, ExtendKeepsTheLowerColumnsAndMakesALadderWithoutTransferLoss) {
  LIVER_OR_SKIP(dir);
  const std::string lower = nav::testing::temporary_path("reduce_lower.navrb");
  const std::string upper = nav::testing::temporary_path("reduce_upper.navrb");
  const std::string mesh_args = "reduce --liver-dir " + dir + " --tets 500 ";
  const auto made =
      run_navtool(mesh_args + "--method pod --r 6 --force corotational --samples 30 --out " + lower, "2>/dev/null");
  ASSERT_EQ(made.exit_code, 0) << made.output;
  const auto run =
      run_navtool(mesh_args + "--extend " + lower + " --r 10 --samples 30 --load-scale 3 --out " + upper + " --json",
                  "2>/dev/null");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("\"lower_r\": 6"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("\"r\": 10"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("\"force\": \"corotational\""), std::string::npos) << run.output;
  const std::vector<double> extension = json_array(run.output, "extension_energy_fraction");
  ASSERT_EQ(extension.size(), 4u) << run.output;
  for (std::size_t k = 1; k < extension.size(); ++k) EXPECT_GE(extension[k], extension[k - 1]);
  EXPECT_LE(extension.back(), 1.0 + 1e-12);

  const nav::TetMesh mesh = nav::load_liver_mesh(dir, 500).value();
  const auto small = nav::load_reduced_basis(lower, &mesh);
  const auto big = nav::load_reduced_basis(upper, &mesh);
  ASSERT_TRUE(small.ok() && big.ok()) << (small.ok() ? big.error().describe() : small.error().describe());
  ASSERT_EQ(big.value().basis_size, 10);
  EXPECT_EQ(big.value().force_kind, nav::ReducedForceKind::corotational_cubature);
  EXPECT_FALSE(big.value().sample_tets.empty());
  ASSERT_EQ(big.value().training_q_bound.size(), 10u);
  const std::size_t kept = small.value().basis.size();  // the 6 lower columns, column-major
  double largest = 0.0, difference = 0.0;
  for (std::size_t i = 0; i < kept; ++i) {
    largest = std::max(largest, std::abs(small.value().basis[i]));
    difference = std::max(difference, std::abs(big.value().basis[i] - small.value().basis[i]));
  }
  EXPECT_LE(difference, 1e-12 * largest);
  std::printf("kept columns: largest difference %.3g (largest entry %.3g)\n", difference, largest);
  // The upper rung trained on 3 times the needle and diaphragm loads (gravity as before): a
  // wider envelope along the shared columns, by up to that factor.
  double widest = 0.0;
  for (std::size_t i = 0; i < 6; ++i) {
    EXPECT_GE(big.value().training_q_bound[i], small.value().training_q_bound[i] * (1.0 - 1e-9)) << i;
    widest = std::max(widest, big.value().training_q_bound[i] / small.value().training_q_bound[i]);
  }
  std::printf("widest envelope ratio of the shared columns: %.3f\n", widest);
  EXPECT_GT(widest, 1.5);
  EXPECT_LT(widest, 3.5);  // about linear in the load: at most a little beyond 3

  const nav::TissueScene scene = nav::liver_reduction_scene(mesh);
  const std::vector<nav::ReducedRungSpec> rungs{{small.value(), {}}, {big.value(), {}}};
  const auto ladder = nav::make_reduced_ladder_model(
      mesh, scene, nav::reduction_solver_options(nav::ReducedForceKind::corotational_cubature), rungs, false, {});
  ASSERT_TRUE(ladder.ok()) << ladder.error().describe();
  EXPECT_LT(ladder.value().transfer_loss(0), 1e-9);

  // A lower artifact that does not fit: of another mesh, not smaller than --r, of another law.
  const std::string cube = nav::testing::test_data_path("mesh/cube.vtu");
  const struct {
    std::string arguments, expected;
  } cases[] = {
      {"reduce --mesh " + cube + " --unit m --extend " + lower + " --r 10 --out " + upper, "belongs to another mesh"},
      {mesh_args + "--extend " + lower + " --r 6 --out " + upper,
       "--r 6 must be above the 6 columns of the lower rung " + lower},
      {mesh_args + "--extend " + lower + " --r 8 --force linear --out " + upper,
       "--force linear differs from the lower rung's"},
  };
  for (const auto& c : cases) {
    const auto refused = run_navtool(c.arguments);
    EXPECT_EQ(refused.exit_code, 2) << c.arguments << "\n" << refused.output;
    EXPECT_NE(refused.output.find(c.expected), std::string::npos) << c.arguments << "\n" << refused.output;
    EXPECT_NE(refused.output.find(lower), std::string::npos) << c.arguments << "\n" << refused.output;
  }
}

/// The integer after `"key": ` in `text` (-1 if absent).
int json_int(const std::string& text, const std::string& key) {
  const std::size_t at = text.find("\"" + key + "\": ");
  return at == std::string::npos ? -1 : std::atoi(text.c_str() + at + key.size() + 4);
}

TEST(NavtoolReduce, AWidenedTrainingLeavesOutAndNamesTheLoadsTheFullOrderCannotSolve) {
  LIVER_OR_SKIP(dir);
  const std::string lower = nav::testing::temporary_path("reduce_wide_lower.navrb");
  const std::string upper = nav::testing::temporary_path("reduce_wide_upper.navrb");
  const std::string mesh_args = "reduce --liver-dir " + dir + " --tets 500 ";
  const auto made = run_navtool(
      mesh_args + "--method pod --r 6 --force corotational --samples 30 --out " + lower + " --json", "2>/dev/null");
  ASSERT_EQ(made.exit_code, 0) << made.output;
  EXPECT_NE(made.output.find("\"skipped_loads\": []"), std::string::npos) << made.output;
  // 12 times the needle forces and diaphragm displacements: the diaphragm moves (6 cm) invert
  // elements of the full order; they are left out, the rest trains the upper rung.
  const auto run =
      run_navtool(mesh_args + "--extend " + lower + " --r 10 --samples 30 --load-scale 12 --out " + upper + " --json",
                  "2>/dev/null");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const std::size_t at = run.output.find("\"skipped_loads\": [");
  ASSERT_NE(at, std::string::npos) << run.output;
  const std::string skipped = run.output.substr(at, run.output.find(']', at) - at);
  EXPECT_NE(skipped.find("\"diaphragm 0\""), std::string::npos) << run.output;
  const auto left_out =
      static_cast<int>(std::count(skipped.begin(), skipped.end(), '"')) / 2 - 1;  // less the key's own quotes
  const auto& fractions = nav::StaticSolveOptions{}.snapshot_fractions;
  EXPECT_EQ(json_int(run.output, "training_loads"),
            json_int(made.output, "training_loads") - left_out * static_cast<int>(fractions.size()));
  const nav::TetMesh mesh = nav::load_liver_mesh(dir, 500).value();
  const auto big = nav::load_reduced_basis(upper, &mesh);
  ASSERT_TRUE(big.ok()) << big.error().describe();
  EXPECT_EQ(big.value().basis_size, 10);
}

TEST(NavtoolReduce, MakesTheShippedRealLiverScenesTwoArtifactsAsItsHeaderSays) {
  // apps/navstation/scenes/liver_reduced.yaml on liverFine: r = 20, then r = 32 on three times
  // the loads, written where the scene reads them (build/), and the scene checks on them.
  LIVER_OR_SKIP(dir);
  NAV_REQUIRE_SHARED_DATA(dir + "/liverFine.vtu");
  const std::string scene = nav::testing::example_scene_path("liver_reduced.yaml");
  const std::string lower = nav::testing::example_scene_path("../../../build/liver_fine.navrb");
  const std::string upper = nav::testing::example_scene_path("../../../build/liver_fine_r32.navrb");
  const auto reduced =
      run_navtool("reduce --liver-dir " + dir + " --method pod --r 20 --force corotational --out " + lower + " --json");
  ASSERT_EQ(reduced.exit_code, 0) << reduced.output;
  EXPECT_NE(reduced.output.find("\"tetrahedra\": 22019"), std::string::npos) << reduced.output;
  EXPECT_EQ(json_array(reduced.output, "captured_energy_fraction").size(), 20u) << reduced.output;
  const auto extended = run_navtool("reduce --liver-dir " + dir + " --extend " + lower +
                                    " --r 32 --load-scale 3 --samples 160 --out " + upper + " --json");
  ASSERT_EQ(extended.exit_code, 0) << extended.output;
  EXPECT_NE(extended.output.find("\"lower_r\": 20"), std::string::npos) << extended.output;
  EXPECT_NE(extended.output.find("\"r\": 32"), std::string::npos) << extended.output;
  const auto checked =
      nav::testing::run_command(nav::testing::executable_path("navstation") + " --scene " + scene + " --check 2>&1");
  EXPECT_EQ(checked.exit_code, 0) << checked.output;
}

TEST(NavtoolReduce, BadArgumentsAndMissingFilesExitWithTwoAndSayWhy) {
  const std::string out = nav::testing::temporary_path("reduce_bad.navrb");
  const std::string mesh = nav::testing::test_data_path("mesh/cube.vtu");
  const std::string corrupt = nav::testing::temporary_path("reduce_corrupt.navrb");
  {
    std::ofstream file(corrupt, std::ios::binary);
    file << "NAVRBAS\n not an artifact";
  }
  const struct {
    std::string arguments, expected;
  } cases[] = {
      {"--mesh " + mesh + " --method pod --r 0 --force linear --out " + out, "--r wants a positive basis size"},
      {"--mesh " + mesh + " --method eigen --r 4 --force linear --out " + out, "unknown --method 'eigen'"},
      {"--mesh " + mesh + " --method pod --r 4 --force soft --out " + out, "unknown --force 'soft'"},
      {"--mesh " + mesh + " --method pod --r 4 --force linear", "--out is required"},
      {"--method pod --r 4 --force linear --out " + out, "give either --liver-dir or --mesh"},
      {"--mesh /no/such/mesh.vtu --unit cm --method pod --r 4 --force linear --out " + out, "/no/such/mesh.vtu"},
      {"--mesh " + mesh + " --extend /no/such/lower.navrb --r 4 --out " + out, "--extend: /no/such/lower.navrb"},
      {"--mesh " + mesh + " --extend " + corrupt + " --r 4 --out " + out, "--extend: " + corrupt},
      {"--mesh " + mesh + " --extend " + corrupt + " --method pod --r 4 --out " + out, "drop --method"},
      {"--mesh " + mesh + " --extend " + corrupt + " --r 4 --load-scale 0 --out " + out, "--load-scale wants a factor"},
  };
  for (const auto& c : cases) {
    const auto run = run_navtool("reduce " + c.arguments);
    EXPECT_EQ(run.exit_code, 2) << c.arguments << "\n" << run.output;
    EXPECT_NE(run.output.find(c.expected), std::string::npos) << c.arguments << "\n" << run.output;
  }
}

}  // namespace
