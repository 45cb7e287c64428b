// navdemo, the first program of the main job: the embedded liver under gravity and a probe,
// solved with the neo-Hookean model, linear FEM beside it with its error. The figures are
// bounded (the liver's displacement at this load, the linear rung's error growing with it) and
// the VTU holds the mesh and every field.
#include <gtest/gtest.h>

#include <string>

#include "nav/mesh/vtu_reader.hpp"
#include "support/run_command.hpp"
#include "support/test_data.hpp"

namespace {

/// The text of the case `name` ("gravity: ..." up to the next case).
std::string case_text(const std::string& output, const std::string& name) {
  const std::size_t at = output.find(name + ": neo-Hookean");
  if (at == std::string::npos) return "";
  return output.substr(at, output.find("\n  linear FEM", at) + 200 - at);
}

TEST(Navdemo, SolvesTheLiverWithTheNeoHookeanModelAndShowsTheLinearRungsError) {
  const std::string vtu = nav::testing::temporary_path("navdemo.vtu");
  const auto run = nav::testing::run_command(nav::testing::executable_path("navdemo") + " --out " + vtu + " 2>&1");
  std::printf("%s", run.output.c_str());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const std::string gravity = case_text(run.output, "gravity");
  const std::string probe = case_text(run.output, "gravity + probe");
  ASSERT_FALSE(gravity.empty() || probe.empty()) << run.output;
  for (const std::string& c : {gravity, probe}) {
    // Centimetres under gravity alone on the soft parenchyma (5 kPa), held at its attachments.
    const double max_mm = nav::testing::number_after(c, "max displacement ");
    EXPECT_GT(max_mm, 10.0);
    EXPECT_LT(max_mm, 100.0);
    EXPECT_GT(nav::testing::number_after(c, "tumour displacement "), 2.0);
    // The linear rung misses the large-displacement behaviour: millimetres off, less than the
    // displacement itself.
    const double error_mm = nav::testing::number_after(c, "its error: ");
    EXPECT_GT(error_mm, 0.5);
    EXPECT_LT(error_mm, max_mm);
  }
  // The probe pushes the tumour further than gravity alone.
  EXPECT_GT(nav::testing::number_after(probe, "tumour displacement "),
            nav::testing::number_after(gravity, "tumour displacement "));

  auto mesh = nav::load_vtu_tet_mesh(vtu, nav::LengthUnit::metre);
  ASSERT_TRUE(mesh.ok()) << mesh.error().describe();
  EXPECT_GT(mesh.value().tets.size(), 4000u);
  const std::string text = nav::testing::file_text(vtu);
  for (const char* field :
       {"\"displacement_m_gravity\"", "\"linear_error_m_gravity_probe\"", "\"linear_von_mises_stress_pa_gravity\""})
    EXPECT_NE(text.find(field), std::string::npos) << field;
}

TEST(Navdemo, BadArgumentsExitWithTwo) {
  const auto run = nav::testing::run_command(nav::testing::executable_path("navdemo") + " --size -1 2>&1");
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_NE(run.output.find("--size"), std::string::npos) << run.output;
}

}  // namespace
