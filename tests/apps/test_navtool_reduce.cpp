// navtool reduce, run as a process on the liver at about 1000 tetrahedra: a POD artifact with
// its captured energy per mode and cubature, a vibration-mode artifact with its frequencies,
// both loadable for that mesh (and only that mesh); exit code 2 with a clear message for bad
// arguments and a missing mesh file.
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>
#include <vector>

#include "nav/reduced/reduced_artifact.hpp"
#include "nav/tissue/liver_scenes.hpp"
#include "support/run_command.hpp"
#include "support/test_data.hpp"

namespace {

nav::testing::CommandRun navtool(const std::string& arguments, const std::string& streams = "2>&1") {
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

#define LIVER_OR_SKIP(dir)                                                                                      \
  const std::string dir = nav::testing::shared_data_path("liver");                                             \
  if (!nav::testing::file_exists(dir + "/liver-smoothUV.obj")) GTEST_SKIP() << "shared data missing: " << dir

TEST(NavtoolReduce, PodArtifactReportsEnergyAndCubatureAndLoadsForItsMeshOnly) {
  LIVER_OR_SKIP(dir);
  const std::string out = nav::testing::temporary_path("reduce_pod.navrb");
  const auto run = navtool("reduce --liver-dir " + dir + " --tets 1000 --method pod --r 12 --force corotational --samples 40 --out " +
                           out + " --json", "2>/dev/null");
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
  const auto table = navtool("reduce --liver-dir " + dir + " --tets 1000 --method modes --r 6 --force linear --out " + out);
  ASSERT_EQ(table.exit_code, 0) << table.output;
  EXPECT_NE(table.output.find("frequency (Hz"), std::string::npos) << table.output;
  EXPECT_NE(table.output.find("written: " + out), std::string::npos);
  const auto run = navtool("reduce --liver-dir " + dir + " --tets 1000 --method modes --r 6 --force linear --out " + out +
                           " --json", "2>/dev/null");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const std::vector<double> hz = json_array(run.output, "mode_frequency_hz");
  ASSERT_EQ(hz.size(), 6u) << run.output;
  EXPECT_GT(hz.front(), 0.0);
  for (std::size_t k = 1; k < hz.size(); ++k) EXPECT_GE(hz[k], hz[k - 1]);
  const auto basis = nav::load_reduced_basis(out, nullptr);
  ASSERT_TRUE(basis.ok()) << basis.error().describe();
  EXPECT_EQ(basis.value().source, nav::ReducedBasisSource::linear_modes);
}

TEST(NavtoolReduce, BadArgumentsAndMissingFilesExitWithTwoAndSayWhy) {
  const std::string out = nav::testing::temporary_path("reduce_bad.navrb");
  const std::string mesh = nav::testing::test_data_path("mesh/cube.vtu");
  const struct {
    std::string arguments, expected;
  } cases[] = {
      {"--mesh " + mesh + " --method pod --r 0 --force linear --out " + out, "--r wants a positive basis size"},
      {"--mesh " + mesh + " --method eigen --r 4 --force linear --out " + out, "unknown --method 'eigen'"},
      {"--mesh " + mesh + " --method pod --r 4 --force soft --out " + out, "unknown --force 'soft'"},
      {"--mesh " + mesh + " --method pod --r 4 --force linear", "--out is required"},
      {"--method pod --r 4 --force linear --out " + out, "give either --liver-dir or --mesh"},
      {"--mesh /no/such/mesh.vtu --unit cm --method pod --r 4 --force linear --out " + out, "/no/such/mesh.vtu"},
  };
  for (const auto& c : cases) {
    const auto run = navtool("reduce " + c.arguments);
    EXPECT_EQ(run.exit_code, 2) << c.arguments << "\n" << run.output;
    EXPECT_NE(run.output.find(c.expected), std::string::npos) << c.arguments << "\n" << run.output;
  }
}

}  // namespace
