// navtool mesh make, run as a process: the embedded liver and a label volume are meshed and
// written; bad arguments and broken inputs exit with 2 and a message naming the problem.
#include <gtest/gtest.h>
#include <cstdio>
#include <string>

#include "support/run_command.hpp"
#include "support/test_data.hpp"

namespace {

using NavtoolRun = nav::testing::CommandRun;

NavtoolRun navtool_mesh_make(const std::string& arguments) {
  return nav::testing::run_command(nav::testing::executable_path("navtool") + " mesh make " + arguments + " 2>&1");
}

TEST(NavtoolMeshMake, MeshesTheEmbeddedLiver) {
  const std::string out = nav::testing::temporary_path("embedded_liver.vtu");
  std::remove(out.c_str());
  const NavtoolRun run = navtool_mesh_make("--liver --size 0.012 --out " + out);
  ASSERT_EQ(run.exit_code, 0) << run.output;
  for (const char* expected : {"tetrahedra: ", "nodes: ", "volume: ", "inverted: 0", "min radius ratio: ", "time: "}) {
    EXPECT_NE(run.output.find(expected), std::string::npos) << expected << " missing in " << run.output;
  }
  EXPECT_TRUE(nav::testing::file_exists(out));
}

TEST(NavtoolMeshMake, MeshesALabelVolume) {
  const std::string out = nav::testing::temporary_path("ball_labels.vtu");
  std::remove(out.c_str());
  const NavtoolRun run = navtool_mesh_make("--labels " + nav::testing::test_data_path("mesher/ball.mha") +
                                           " --unit mm --size 0.0015 --out " + out);
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_TRUE(nav::testing::file_exists(out));
}

TEST(NavtoolMeshMake, BadArgumentsExitWithTwoAndSayWhy) {
  const struct {
    const char* arguments;
    const char* message;
  } cases[] = {{"--liver --size -1 --out x.vtu", "--size"},
               {"--liver --size 0.01", "--out"},
               {"--size 0.01 --out x.vtu", "--liver"},
               {"--liver --surface a.obj --size 0.01 --out x.vtu", "one of"},
               {"--liver --size 0.01 --out x.vtu --bogus", "'--bogus'"},
               {"--labels a.mha --unit inch --size 0.01 --out x.vtu", "inch"},
               {"--liver --size 1e-6 --out x.vtu", "too small"}};
  for (const auto& c : cases) {
    const NavtoolRun run = navtool_mesh_make(c.arguments);
    EXPECT_EQ(run.exit_code, 2) << c.arguments;
    EXPECT_NE(run.output.find(c.message), std::string::npos) << c.arguments << ": " << run.output;
  }
}

TEST(NavtoolMeshMake, BrokenInputNamesFileAndLine) {
  const std::string broken = nav::testing::test_data_path("mesher/truncated.mha");
  const NavtoolRun run = navtool_mesh_make("--labels " + broken + " --size 0.001 --out x.vtu");
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_NE(run.output.find(broken + ":11: ElementDataFile"), std::string::npos) << run.output;
}

}  // namespace
