// navbench tradeoff --quick writes one JSON record per rung with every required field, full-
// order and reduced rungs side by side, and a log-log SVG with the Pareto front drawn.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "support/run_command.hpp"
#include "support/test_data.hpp"

namespace {

std::size_t count_of(const std::string& text, const std::string& part) {
  std::size_t count = 0;
  for (std::size_t at = text.find(part); at != std::string::npos; at = text.find(part, at + 1)) ++count;
  return count;
}

TEST(NavbenchTradeoff, QuickRunWritesRecordsAndParetoPlot) {
  const std::string liver = nav::testing::shared_data_path("liver/liver-smoothUV.obj");
  if (!nav::testing::file_exists(liver)) GTEST_SKIP() << "shared data missing: " << liver;
  const std::filesystem::path json = nav::testing::temporary_path("navbench_tradeoff_quick.json");
  const std::filesystem::path svg = nav::testing::temporary_path("navbench_tradeoff_quick.svg");
  const auto run = nav::testing::run_command(nav::testing::executable_path("navbench") + " tradeoff --quick --json " +
                                             json.string() + " --plot " + svg.string() + " 2>&1");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const std::string records = nav::testing::file_text(json.string());
  const std::size_t record_count = count_of(records, "\"model\"");
  EXPECT_GE(record_count, 6u) << records;
  for (const char* field : {"\"r\"", "\"sampled_elements\"", "\"tetrahedra\"", "\"step_us_median\"", "\"step_us_p99\"",
                            "\"error_rms_m\"", "\"error_max_m\"", "\"target_error_m\"", "\"memory_bytes\""})
    EXPECT_EQ(count_of(records, field), record_count) << field;
  for (const char* model : {"\"linear_full\"", "\"corotational_full\"", "\"pod_corotational\"", "\"pod_linear\"", "\"modes_linear\""})
    EXPECT_NE(records.find(model), std::string::npos) << model;
  EXPECT_EQ(records.find("nan"), std::string::npos);
  EXPECT_EQ(records.find("inf"), std::string::npos);

  const std::string plot = nav::testing::file_text(svg.string());
  EXPECT_EQ(plot.rfind("<svg", 0), 0u);
  EXPECT_NE(plot.find("</svg>"), std::string::npos);
  EXPECT_EQ(count_of(plot, "class=\"pareto\""), 1u);  // one mesh in the quick run: one front
  EXPECT_NE(plot.find("(Pareto front)"), std::string::npos);
  EXPECT_GE(count_of(plot, "<title>"), record_count);
}

// Bad command lines: no --plot, no --json.
TEST(NavbenchTradeoff, MissingOutputsAreAnError) {
  const std::string navbench = nav::testing::executable_path("navbench");
  const auto no_plot = nav::testing::run_command(navbench + " tradeoff --json /tmp/x.json 2>&1");
  EXPECT_EQ(no_plot.exit_code, 2);
  EXPECT_NE(no_plot.output.find("--plot"), std::string::npos) << no_plot.output;
  const auto no_json = nav::testing::run_command(navbench + " tradeoff --plot /tmp/x.svg 2>&1");
  EXPECT_EQ(no_json.exit_code, 2);
}

}  // namespace
