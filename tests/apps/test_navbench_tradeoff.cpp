// navbench tradeoff --quick writes one JSON record per rung with every required field, full-
// order and reduced rungs side by side, errors against the neo-Hookean reference within
// bounds and in the order the models' physics gives, and a log-log SVG whose Pareto front is
// the records' own.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "support/run_command.hpp"
#include "support/test_data.hpp"

namespace {

std::size_t count_of(const std::string& text, const std::string& part) {
  std::size_t count = 0;
  for (std::size_t at = text.find(part); at != std::string::npos; at = text.find(part, at + 1)) ++count;
  return count;
}

/// One record of the JSON: its model, r, step median and errors.
struct TradeoffRecord {
  std::string model;
  double r = 0.0, step_us = 0.0, error_rms_m = 0.0, error_pct = 0.0, vs_corotational_pct = 0.0;
};

std::vector<TradeoffRecord> tradeoff_records_of(const std::string& json) {
  std::vector<TradeoffRecord> records;
  for (std::size_t at = json.find("{\"mesh\""); at != std::string::npos; at = json.find("{\"mesh\"", at + 1)) {
    const std::string line = json.substr(at, json.find('}', at) - at);
    const std::size_t model = line.find("\"model\": \"") + 10;
    records.push_back({line.substr(model, line.find('"', model) - model), nav::testing::number_after(line, "\"r\": "),
                       nav::testing::number_after(line, "\"step_us_median\": "),
                       nav::testing::number_after(line, "\"error_rms_m\": "),
                       nav::testing::number_after(line, "\"error_rms_pct\": "),
                       nav::testing::number_after(line, "\"error_rms_vs_corotational_pct\": ")});
  }
  return records;
}

const TradeoffRecord* find(const std::vector<TradeoffRecord>& records, const std::string& model, double r) {
  for (const TradeoffRecord& record : records)
    if (record.model == model && record.r == r) return &record;
  return nullptr;
}

/// The records no other record beats in both step time and error (as the plot draws them).
std::size_t pareto_count(const std::vector<TradeoffRecord>& records) {
  std::size_t count = 0;
  for (const TradeoffRecord& a : records) {
    bool dominated = false;
    for (const TradeoffRecord& b : records)
      dominated = dominated || (&a != &b && b.step_us <= a.step_us && b.error_rms_m <= a.error_rms_m &&
                                (b.step_us < a.step_us || b.error_rms_m < a.error_rms_m));
    count += dominated ? 0 : 1;
  }
  return count;
}

TEST(NavbenchTradeoff, QuickRunWritesRecordsAndParetoPlot) {
  const std::string liver = nav::testing::shared_data_path("liver/liver-smoothUV.obj");
  NAV_REQUIRE_SHARED_DATA(liver);
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
  for (const char* model :
       {"\"linear_full\"", "\"corotational_full\"", "\"pod_corotational\"", "\"pod_linear\"", "\"modes_linear\""})
    EXPECT_NE(records.find(model), std::string::npos) << model;
  EXPECT_EQ(records.find("nan"), std::string::npos);
  EXPECT_EQ(records.find("inf"), std::string::npos);

  // The errors (deterministic: the same loads, the same solves), against the neo-Hookean
  // reference in % of its displacement: corotational is the closest full-order rung and linear
  // clearly worse at these displacements; a POD basis on corotational forces converges to the
  // full-order corotational model as r grows; every linear rung keeps the linear model's error.
  const std::vector<TradeoffRecord> parsed = tradeoff_records_of(records);
  ASSERT_EQ(parsed.size(), record_count);
  const TradeoffRecord* corotational = find(parsed, "corotational_full", 0);
  const TradeoffRecord* linear = find(parsed, "linear_full", 0);
  const TradeoffRecord* pod4 = find(parsed, "pod_corotational", 4);
  const TradeoffRecord* pod16 = find(parsed, "pod_corotational", 16);
  ASSERT_TRUE(corotational && linear && pod4 && pod16) << records;
  EXPECT_LE(corotational->error_pct, 6.0);
  EXPECT_GE(linear->error_pct, 1.8 * corotational->error_pct);
  EXPECT_LE(pod16->vs_corotational_pct, 6.0);
  EXPECT_LT(pod16->error_rms_m, pod4->error_rms_m);
  EXPECT_LE(pod4->vs_corotational_pct, 12.0);
  for (const TradeoffRecord& r : parsed) {
    EXPECT_GT(r.error_pct, 0.0) << r.model;
    EXPECT_LE(r.error_pct, 15.0) << r.model << " r " << r.r;
    if (r.model.find("linear") != std::string::npos) {
      EXPECT_GE(r.vs_corotational_pct, 10.0) << r.model;
    }
  }

  const std::string plot = nav::testing::file_text(svg.string());
  EXPECT_EQ(plot.rfind("<svg", 0), 0u);
  EXPECT_NE(plot.find("</svg>"), std::string::npos);
  EXPECT_EQ(count_of(plot, "class=\"pareto\""), 1u);                  // one mesh in the quick run: one front
  EXPECT_EQ(count_of(plot, "(Pareto front)"), pareto_count(parsed));  // the front of the records' own figures
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
