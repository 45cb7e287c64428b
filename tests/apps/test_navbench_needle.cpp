// navbench needle --quick writes one JSON record per case (the needle alone at 20, 30 and 40
// elements; with 8, 16 and 32 path constraints; coupled to the full-order liver with the tissue
// every tick and every 10 ticks; in the reduced liver with 8, 16 and 32 points at each element
// count, the 32-point case once per kernel variant at the default sweeps and once at 10) with
// finite times and residuals within the solver's bound, the kernel variants giving the same
// residual to the last digit (the same bits), and the force-depth SVG next to the JSON with
// its four curves (total, stiffness, cutting, friction).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <regex>
#include <string>
#include <vector>

#include "support/run_command.hpp"
#include "support/test_data.hpp"

namespace {

/// One record of the JSON, the fields the checks read.
struct Record {
  std::string name, kernel_isa, residual_text;
  int elements = 0, points = 0, ratio = 0, sweeps = 0;
  double median_us = 0.0, p99_us = 0.0, residual_m = 0.0;
};

std::vector<Record> records_of(const std::string& json) {
  const std::regex record(
      R"re(\{"case": "([a-z_]+)", "elements": (\d+), "constraint_points": (\d+), "rows": \d+, "tetrahedra": \d+, )re"
      R"re("needle_steps_per_tissue_step": (\d+), "basis_size": \d+, "kernel_isa": "([a-z0-9]+)", "step_us_median": ([-0-9.e+a-z]+), )re"
      R"re("gauss_seidel_sweeps": (\d+), "step_us_p99": ([-0-9.e+a-z]+), "residual_m": ([-0-9.e+a-z]+)\})re");
  std::vector<Record> records;
  for (auto it = std::sregex_iterator(json.begin(), json.end(), record); it != std::sregex_iterator(); ++it) {
    const std::smatch& m = *it;
    Record r;
    r.name = m[1];
    r.elements = std::stoi(m[2]);
    r.points = std::stoi(m[3]);
    r.ratio = std::stoi(m[4]);
    r.kernel_isa = m[5];
    r.median_us = std::stod(m[6]);
    r.sweeps = std::stoi(m[7]);
    r.p99_us = std::stod(m[8]);
    r.residual_text = m[9];
    r.residual_m = std::stod(m[9]);
    records.push_back(r);
  }
  return records;
}

int count_of(const std::vector<Record>& records, const std::string& name, int elements, int points) {
  int count = 0;
  for (const Record& r : records) count += r.name == name && r.elements == elements && r.points == points ? 1 : 0;
  return count;
}

}  // namespace

TEST(NavbenchNeedle, QuickRunWritesRecordsAndForceProfile) {
  const std::filesystem::path json = nav::testing::temporary_path("navbench_needle_quick.json");
  const std::filesystem::path svg = json.parent_path() / "navbench_needle_quick_force_profile.svg";
  std::filesystem::remove(svg);
  const auto run = nav::testing::run_command(nav::testing::executable_path("navbench") + " needle --quick --json " +
                                             json.string() + " 2>&1");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const std::string text = nav::testing::file_text(json.string());
  const std::vector<Record> records = records_of(text);
  ASSERT_EQ(records.size(), static_cast<std::size_t>(std::count(text.begin(), text.end(), '{')))
      << "a record the pattern did not read";

  for (int elements : {20, 30, 40}) {
    EXPECT_EQ(count_of(records, "needle_alone", elements, 0), 1) << elements;
    EXPECT_EQ(count_of(records, "coupled_reduced_liver", elements, 8), 1) << elements;
    EXPECT_EQ(count_of(records, "coupled_reduced_liver", elements, 16), 1) << elements;
    EXPECT_GE(count_of(records, "coupled_reduced_liver", elements, 32), 2)
        << elements;  // the baseline kernels and 10 sweeps at least
  }
  for (int points : {8, 16, 32}) EXPECT_EQ(count_of(records, "needle_constraints", 30, points), 1) << points;
  EXPECT_EQ(count_of(records, "needle_constraints", 20, 32), 1);

  std::map<int, std::vector<const Record*>> liver_32_at_default_sweeps;  // by element count
  int full_order = 0, at_10_sweeps = 0;
  for (const Record& r : records) {
    SCOPED_TRACE(r.name + " " + std::to_string(r.elements) + " elements, " + std::to_string(r.points) + " points, " +
                 r.kernel_isa);
    EXPECT_TRUE(std::isfinite(r.median_us) && r.median_us > 0.0);
    EXPECT_GE(r.p99_us, r.median_us);
    EXPECT_TRUE(r.residual_m >= 0.0 && r.residual_m < 10e-6);  // the solver's bound on the constraint laws
    if (r.name == "coupled_full_order_corotational") {
      ++full_order;
      EXPECT_TRUE(r.ratio == 1 || r.ratio == 10);
    }
    if (r.name == "coupled_reduced_liver" && r.points == 32) {
      if (r.sweeps == 10)
        ++at_10_sweeps;
      else
        liver_32_at_default_sweeps[r.elements].push_back(&r);
    }
  }
  EXPECT_EQ(full_order, 2);
  EXPECT_EQ(at_10_sweeps, 3);
  for (const auto& [elements, variants] : liver_32_at_default_sweeps) {
    ASSERT_FALSE(variants.empty());
    EXPECT_EQ(variants.front()->kernel_isa, "baseline");
    for (const Record* r : variants)
      EXPECT_EQ(r->residual_text, variants.front()->residual_text) << elements << " elements, " << r->kernel_isa;
  }

  ASSERT_TRUE(std::filesystem::exists(svg));
  const std::string plot = nav::testing::file_text(svg.string());
  EXPECT_NE(plot.find("<svg"), std::string::npos);
  std::size_t curves = 0;
  for (std::size_t at = plot.find("<polyline"); at != std::string::npos; at = plot.find("<polyline", at + 1)) ++curves;
  EXPECT_EQ(curves, 4u);
  for (const char* legend : {">total<", ">stiffness (capsule)<", ">cutting<", ">shaft friction<"})
    EXPECT_NE(plot.find(legend), std::string::npos) << legend;
}
