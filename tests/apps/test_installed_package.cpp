// The installed CMake package as station software uses it: this build is installed into a
// temporary prefix, apps/embedding (a separate project) finds it with find_package(navrt),
// builds with warnings as errors, and runs its embedded operating loop: the station
// software's own tracker and ultrasound threads feed the loop, its real-time thread ticks it
// at 1 kHz for 7 s, and the example scores the tumour against the full-order liver.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include "support/run_command.hpp"
#include "support/test_data.hpp"

namespace nav {
namespace {

using testing::run_command;

std::string quoted(const std::string& text) { return "'" + text + "'"; }

/// The example's last line: "figures: misses tracker_samples tumour_points now ahead marker tip finite degraded".
struct LoopFigures {
  long long misses = -1, tracker_samples = 0, tumour_points = 0;
  double now_mm = NAN, ahead_mm = NAN, marker_mm = NAN, tip_mm = NAN;
  int finite = 0, degraded = 1;
};

LoopFigures figures_of(const std::string& output) {
  LoopFigures f;
  const std::size_t at = output.find("figures: ");
  if (at == std::string::npos ||
      std::sscanf(output.c_str() + at, "figures: %lld %lld %lld %lf %lf %lf %lf %d %d", &f.misses, &f.tracker_samples,
                  &f.tumour_points, &f.now_mm, &f.ahead_mm, &f.marker_mm, &f.tip_mm, &f.finite, &f.degraded) != 9)
    ADD_FAILURE() << "no figures line";
  return f;
}

TEST(InstalledPackage, StationSoftwareFindsItBuildsAgainstItAndRunsTheOperatingLoop) {
  const std::string prefix = testing::temporary_path("navrt-installed");
  const std::string build = testing::temporary_path("navrt-embedding-build");
  std::filesystem::remove_all(prefix);
  std::filesystem::remove_all(build);

  const auto install =
      run_command("cmake --install " + quoted(NAV_BUILD_DIR) + " --prefix " + quoted(prefix) + " 2>&1");
  ASSERT_EQ(install.exit_code, 0) << install.output;
  EXPECT_TRUE(std::filesystem::exists(prefix + "/include/nav/loop/operating_loop.hpp"));
  // The compile definitions the headers need travel with the package: nothing to repeat by hand.
  const std::string targets = testing::file_text(prefix + "/lib/cmake/navrt/navrtTargets.cmake");
  EXPECT_NE(targets.find("EIGEN_GEMM_TO_COEFFBASED_THRESHOLD=64"), std::string::npos) << targets.substr(0, 2000);

  const std::string flags = std::string("-Wall -Wextra -Wpedantic -Werror ") + NAV_SANITIZE_FLAGS;
  const auto configure =
      run_command("cmake -S " + quoted(std::string(NAV_SOURCE_DIR) + "/apps/embedding") + " -B " + quoted(build) +
                  " -DCMAKE_BUILD_TYPE=Release -DCMAKE_PREFIX_PATH=" + quoted(prefix) +
                  " -DCMAKE_CXX_COMPILER=" + quoted(NAV_CXX_COMPILER) + " -DCMAKE_CXX_FLAGS=" + quoted(flags) +
                  " -DCMAKE_EXE_LINKER_FLAGS=" + quoted(NAV_SANITIZE_FLAGS) + " 2>&1");
  ASSERT_EQ(configure.exit_code, 0) << configure.output;
  const auto compile = run_command("cmake --build " + quoted(build) + " -j2 2>&1");
  ASSERT_EQ(compile.exit_code, 0) << compile.output;

  // 7 s: the breathing predictor (3 s breaths) is ready after two breaths; a tick more than
  // 100 ms late is a miss (generous: the host runs other test programs and sanitizers). This
  // shared host stops its cores for a few hundred milliseconds at times (as the real-time
  // programs' cases, toolchain/run), so a run with misses is run again, up to three runs in all,
  // each printed; the figures are the last run's.
  LoopFigures f;
  for (int run = 1; run <= 3; ++run) {
    const auto loop = run_command(quoted(build + "/embedded_operating_loop") + " 7 100 2>&1");
    std::printf("run %d:\n%s", run, loop.output.c_str());
    ASSERT_EQ(loop.exit_code, 0) << loop.output;
    f = figures_of(loop.output);
    if (f.misses == 0) break;
  }
  EXPECT_EQ(f.misses, 0);
  EXPECT_EQ(f.finite, 1);
  EXPECT_EQ(f.degraded, 0) << "an input is still degraded at the end";
  EXPECT_GE(f.tracker_samples, 1200);  // 3 markers at 60 Hz over 7 s: 1260
  EXPECT_GE(f.tumour_points, 130);     // at 20 Hz: 140
  // Against the full-order liver (quasi-static corotational solves, independent of the reduced
  // model): with 1 mm ultrasound noise the tumour is within 1.3 mm RMS (measured 0.95-1.02 mm),
  // and better than the liver following the respiratory marker exactly (1.42-1.47 mm: the
  // marker is only a surrogate).
  EXPECT_LT(f.now_mm, 1.3);
  EXPECT_LT(f.ahead_mm, 1.4);
  EXPECT_LT(f.now_mm, 0.85 * f.marker_mm);
  EXPECT_LT(f.tip_mm, 2.0);  // 0.25 mm tracker noise, extrapolated over the tracker's delay
}

}  // namespace
}  // namespace nav
