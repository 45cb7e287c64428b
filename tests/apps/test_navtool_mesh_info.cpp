// navtool mesh info, run as a process: JSON and table output on the real liver mesh, exit code
// 2 with the Error's describe() on stderr for a broken file and for bad arguments.
#include <gtest/gtest.h>
#include <cstdio>

#include "support/run_command.hpp"
#include "support/test_data.hpp"

namespace {

using ProcessRun = nav::testing::CommandRun;

/// Runs navtool with `arguments` through the shell; `streams` picks what is captured
/// ("2>&1" for both, "2>&1 >/dev/null" for stderr alone).
ProcessRun navtool(const std::string& arguments, const std::string& streams = "2>/dev/null") {
  return nav::testing::run_command(nav::testing::executable_path("navtool") + " " + arguments + " " + streams);
}

std::string liver_vtu() { return nav::testing::shared_data_path("liver/liverFine.vtu"); }

TEST(NavtoolMeshInfo, LiverAsJsonHasItsCountsAndAClosedBoundary) {
  NAV_REQUIRE_SHARED_DATA(liver_vtu());
  const ProcessRun run = navtool("mesh info " + liver_vtu() + " --unit cm --json");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  for (const std::string& expected :
       {"\"file\": \"" + liver_vtu() + "\"", std::string("\"unit\": \"cm\""), std::string("\"nodes\": 4293"),
        std::string("\"tetrahedra\": 22019"), std::string("\"inverted\": 0"), std::string("\"degenerate\": 11"),
        std::string("\"unreferenced_nodes\": 0"), std::string("\"boundary_closed\": true"),
        std::string("\"volume_m3\": 3.89"), std::string("\"min_quality\": 0.01"),
        std::string("\"min_dihedral_deg\": ")}) {
    EXPECT_NE(run.output.find(expected), std::string::npos) << "missing " << expected << " in " << run.output;
  }
  EXPECT_EQ(run.output.front(), '{');
  EXPECT_EQ(run.output.substr(run.output.size() - 2), "}\n");
}

TEST(NavtoolMeshInfo, DefaultUnitIsTheMetreAndTheTableIsReadable) {
  const std::string cube = nav::testing::test_data_path("mesh/cube_v41.msh");
  const ProcessRun run = navtool("mesh info " + cube);
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("unit                           m\n"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("tetrahedra                     5\n"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("volume_m3                      1\n"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("boundary_closed                yes\n"), std::string::npos) << run.output;
}

TEST(NavtoolMeshInfo, SurfaceFileReportsClosedness) {
  const ProcessRun run = navtool("mesh info " + nav::testing::test_data_path("mesh/cube.obj") + " --unit mm --json");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("\"triangles\": 12"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("\"closed\": true"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("\"volume_m3\": 1e-09"), std::string::npos) << run.output;
}

TEST(NavtoolMeshInfo, BrokenFileExitsTwoWithTheErrorOnStderr) {
  const std::string broken = nav::testing::test_data_path("mesh/broken/vtu_connectivity_out_of_range.vtu");
  const ProcessRun run = navtool("mesh info " + broken + " --json", "2>&1 >/dev/null");
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_EQ(run.output, broken + ":32: connectivity: point index 60 is out of range (8 points)\n");
  EXPECT_EQ(navtool("mesh info " + broken + " --json").output, "");  // nothing on stdout
}

TEST(NavtoolMeshInfo, BadArgumentsExitTwo) {
  EXPECT_EQ(navtool("mesh info").exit_code, 2);
  EXPECT_EQ(navtool("mesh info cube.vtu --unit inch").exit_code, 2);
  EXPECT_EQ(navtool("mesh info cube.vtu --verbose").exit_code, 2);
  EXPECT_EQ(navtool("mesh info /nonexistent/cube.vtu").exit_code, 2);
}

}  // namespace
