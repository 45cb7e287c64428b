// navbench connective --quick writes the frames sweep, the liver held by two ligaments against
// fixed nodes, and the stability of the coupling, with every required field.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "support/run_command.hpp"
#include "support/test_data.hpp"

TEST(NavbenchConnective, QuickRunWritesSweepLiverCostAndStability) {
  const std::filesystem::path json = nav::testing::temporary_path("navbench_connective_quick.json");
  const auto run = nav::testing::run_command(nav::testing::executable_path("navbench") + " connective --quick --json " +
                                             json.string() + " 2>&1");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const std::string records = nav::testing::file_text(json.string());
  for (const char* field : {"\"frames\"", "\"points\"", "\"pairs\"", "\"step_us_median\"", "\"step_us_p99\"",
                            "\"difference_max_m\"", "\"difference_rms_m\"", "\"stable\"", "\"stabilising_spring_n_m\""})
    EXPECT_NE(records.find(field), std::string::npos) << field;
  for (const char* name :
       {"\"frames_sweep\"", "\"liver_fixed_nodes\"", "\"liver_two_ligaments\"", "\"coupling_plain_staggered\"",
        "\"coupling_stabilised\"", "\"banded_cholesky\"", "\"cg60_block_jacobi\""})
    EXPECT_NE(records.find(name), std::string::npos) << name;
  EXPECT_EQ(records.find("nan"), std::string::npos);
  const auto missing = nav::testing::run_command(nav::testing::executable_path("navbench") + " connective 2>&1");
  EXPECT_EQ(missing.exit_code, 2);
}
