// The installed CMake package as station software uses it: this build is installed into a
// temporary prefix, apps/embedding (a separate project) finds it with find_package(navrt),
// builds with warnings as errors, and runs its embedded real-time liver loop.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <string>

#include "support/run_command.hpp"
#include "support/test_data.hpp"

namespace nav {
namespace {

using testing::run_command;

std::string quoted(const std::string& text) { return "'" + text + "'"; }

TEST(InstalledPackage, StationSoftwareFindsItBuildsAgainstItAndRunsTheEmbeddedLoop) {
  const std::string prefix = testing::temporary_path("navrt-installed");
  const std::string build = testing::temporary_path("navrt-embedding-build");
  std::filesystem::remove_all(prefix);
  std::filesystem::remove_all(build);

  const auto install = run_command("cmake --install " + quoted(NAV_BUILD_DIR) + " --prefix " + quoted(prefix) + " 2>&1");
  ASSERT_EQ(install.exit_code, 0) << install.output;
  EXPECT_TRUE(std::filesystem::exists(prefix + "/include/nav/tissue/tet_fem_model.hpp"));

  const std::string flags = std::string("-Wall -Wextra -Wpedantic -Werror ") + NAV_SANITIZE_FLAGS;
  const auto configure = run_command(
      "cmake -S " + quoted(std::string(NAV_SOURCE_DIR) + "/apps/embedding") + " -B " + quoted(build) +
      " -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH=" + quoted(prefix) + " -DCMAKE_CXX_COMPILER=" +
      quoted(NAV_CXX_COMPILER) + " -DCMAKE_CXX_FLAGS=" + quoted(flags) + " -DCMAKE_EXE_LINKER_FLAGS=" +
      quoted(NAV_SANITIZE_FLAGS) + " 2>&1");
  ASSERT_EQ(configure.exit_code, 0) << configure.output;
  const auto compile = run_command("cmake --build " + quoted(build) + " -j2 2>&1");
  ASSERT_EQ(compile.exit_code, 0) << compile.output;

  const auto loop = run_command(quoted(build + "/embedded_liver_loop") + " 100 2>&1");
  std::printf("%s", loop.output.c_str());
  ASSERT_EQ(loop.exit_code, 0) << loop.output;
  const auto at = loop.output.find("tumour moved ");
  ASSERT_NE(at, std::string::npos);
  const double moved_mm = std::stod(loop.output.substr(at + 13));
  // The probe presses 10 mm above the tumour, which sits deep in the lobe: it moves, less.
  EXPECT_GT(moved_mm, 0.2);
  EXPECT_LT(moved_mm, 10.0);
}

}  // namespace
}  // namespace nav
