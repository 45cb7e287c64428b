// navbridge igtl as a station engineer runs it: on a scene with an openigtlink section it
// connects to the PlusServer the scene names (here the test's stand-in on loopback), prints
// what it bridged each second and exits 0 after --seconds, or runs until stopped by a signal;
// a scene without the section, or a bad command line, is refused with what is missing.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <thread>

#include "bridge_test_support.hpp"
#include "nav/igtl/igtl_stream.hpp"
#include "support/run_command.hpp"

namespace nav::testing {
namespace {

constexpr std::uint32_t kDomain = 222;

/// `text` written to a scene file of the test's own; its path.
std::string written_scene(const std::string& name, const std::string& text) {
  const std::filesystem::path path = std::filesystem::temp_directory_path() / ("navbridge_" + name + ".yaml");
  std::ofstream(path) << text;
  return path.string();
}

TEST(Navbridge, BridgesAPlusServerForItsSecondsAndSaysWhatItDid) {
  auto plus = igtl::Listener::listen({"127.0.0.1", 0});
  ASSERT_TRUE(plus.ok());
  const std::string scene =
      written_scene("plus", edited(movable_demo_text(), "domain_id: 0", "domain_id: " + std::to_string(kDomain)) +
                                "\nopenigtlink:\n  plus: {connect: 127.0.0.1:" + std::to_string(plus.value().port()) +
                                "}\n  displays: 127.0.0.1:0\n");
  CommandRun run;
  std::thread bridge(
      [&] { run = run_command(executable_path("navbridge") + " igtl --scene " + scene + " --seconds 3 2>&1"); });
  auto connection = plus.value().accept(20 * kNsPerSecond);
  const float identity_mm[3][4] = {{1, 0, 0, 5}, {0, 1, 0, 0}, {0, 0, 1, 0}};
  for (int i = 0; connection.ok() && i < 3; ++i)
    EXPECT_TRUE(connection.value().write(transform_bytes("StylusToTracker", identity_mm, 0)).ok());
  bridge.join();
  ASSERT_TRUE(connection.ok()) << run.output;
  std::printf("%s", run.output.c_str());
  EXPECT_EQ(run.exit_code, 0);
  EXPECT_NE(run.output.find("PlusServer connected"), std::string::npos);
  EXPECT_NE(run.output.find("in 3 poses, 0 frames, 0 skipped, 0 refused"), std::string::npos);
  EXPECT_NE(run.output.find("stopped"), std::string::npos);
}

TEST(Navbridge, WithoutSecondsItRunsUntilStoppedSayingWhatItDidOnceASecond) {
  const std::string scene = written_scene(
      "until_stopped", edited(movable_demo_text(), "domain_id: 0", "domain_id: " + std::to_string(kDomain)) +
                           "\nopenigtlink:\n  displays: 127.0.0.1:0\n");
  const CommandRun run =
      run_command("timeout -s INT 5 " + executable_path("navbridge") + " igtl --scene " + scene + " 2>&1");
  std::printf("%s", run.output.c_str());
  std::size_t status_lines = 0;
  for (std::size_t at = run.output.find("navbridge igtl: in "); at != std::string::npos;
       at = run.output.find("navbridge igtl: in ", at + 1))
    ++status_lines;
  EXPECT_GE(status_lines, 1u);
  EXPECT_LE(status_lines, 5u) << "one status line a second, for the 5 s it ran (its start-up included)";
  EXPECT_NE(run.output.find("navbridge igtl: stopped"), std::string::npos) << "SIGINT stops it cleanly";
}

TEST(Navbridge, ASceneWithoutTheSectionOrABadCommandLineIsRefused) {
  const CommandRun without =
      run_command(executable_path("navbridge") + " igtl --scene " + example_scene_path("demo.yaml") + " 2>&1");
  EXPECT_EQ(without.exit_code, 1);
  EXPECT_NE(without.output.find("openigtlink"), std::string::npos) << without.output;
  const CommandRun usage = run_command(executable_path("navbridge") + " igtl --seconds -1 2>&1");
  EXPECT_EQ(usage.exit_code, 2);
  EXPECT_NE(usage.output.find("usage: navbridge igtl --scene FILE"), std::string::npos) << usage.output;
}

}  // namespace
}  // namespace nav::testing
