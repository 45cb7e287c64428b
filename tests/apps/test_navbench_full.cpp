// navbench full --quick writes one JSON record per (model, mesh, integrator, scene) with every
// required field, and the SVG plot next to it.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "support/run_command.hpp"
#include "support/test_data.hpp"

TEST(NavbenchFull, QuickRunWritesRecordsAndPlot) {
  const std::filesystem::path json = nav::testing::temporary_path("navbench_full_quick.json");
  const auto run = nav::testing::run_command(nav::testing::executable_path("navbench") + " full --quick --json " +
                                             json.string() + " 2>&1");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const std::string records = nav::testing::file_text(json.string());
  for (const char* field : {"\"model\"", "\"tetrahedra\"", "\"integrator\"", "\"step_us_median\"", "\"step_us_p99\"",
                            "\"error_rms_m\"", "\"error_max_m\"", "\"volume_change_pct\""})
    EXPECT_NE(records.find(field), std::string::npos) << field;
  for (const char* model : {"\"linear\"", "\"corotational\"", "\"stvk\"", "\"stvk_penalty\"", "\"mass_spring_volume\""})
    EXPECT_NE(records.find(model), std::string::npos) << model;
  EXPECT_NE(records.find("\"probe_2cm\""), std::string::npos);
  EXPECT_TRUE(std::filesystem::exists(json.parent_path() / "navbench_full_quick.svg"));
}
