// navview end to end: started headless in its own process with the demo scene, it subscribes
// to a publisher in this process (the probe's pose placing the frame included) and writes PNG
// files showing the frame, the needle, the target and the surface where the renderer test says
// they belong; SIGTERM ends it cleanly.
#include <gtest/gtest.h>

#include <csignal>
#include <filesystem>

#include "child_process.hpp"
#include "dds_test_samples.hpp"
#include "nav/core/text_file.hpp"
#include "nav/dds/dds_node.hpp"
#include "nav/view/palette.hpp"
#include "nav/view/png_file.hpp"
#include "navview_placing_pose.hpp"
#include "test_navview_scene.hpp"

namespace nav::view {
namespace {

using nav::testing::ChildProcess;
using namespace nav::view::testing;

const std::string kNavview = std::string(NAV_BIN_DIR) + "/navview";
constexpr TimeNs kMatchTimeoutNs = 30 * kNsPerSecond;

TEST(NavviewHeadless, WritesPngsOfWhatItReceives) {
  const std::filesystem::path out_dir = ::testing::TempDir() + "navview_headless_" + std::to_string(getpid());
  std::filesystem::remove_all(out_dir);
  const std::string square_obj = out_dir.string() + "_square.obj";
  write_scene_triangles_obj(square_obj);
  const std::string scene = out_dir.string() + "_demo.yaml";
  ASSERT_TRUE(write_text_file(scene, nav::testing::movable_demo_text()).ok());
  ChildProcess navview({kNavview,          "--headless",
                        "--out-dir",       out_dir.string(),
                        "--period-ms",     "50",
                        "--duration-s",    "120",
                        "--surface-mesh",  square_obj,
                        "--unit",          "mm",
                        "--panel-height",  std::to_string(kPanelHeightPx),
                        "--azimuth-deg",   "0",
                        "--elevation-deg", "0",
                        "--scene",         scene,
                        "--domain",        "162"},
                       out_dir.string() + ".log");
  ASSERT_TRUE(navview.started());

  auto station = dds::DdsNode::create(dds::testing::local_network(162));
  ASSERT_TRUE(station.ok()) << station.error().describe();
  dds::DdsNode& node = *station.value();
  ASSERT_TRUE(SceneStream::advertise(node, kMatchTimeoutNs)) << navview.log();

  SceneStream stream;
  std::set<std::string> looked_at;
  std::string matching_png;
  const bool shown = dds::testing::wait_until(
      [&] {
        stream.publish(node);
        std::this_thread::sleep_for(std::chrono::milliseconds(20));
        for (const std::string& png : png_files(out_dir)) {
          if (!looked_at.insert(png).second) continue;
          auto image = read_png(png);
          EXPECT_TRUE(image.ok()) << image.error().describe();
          if (image.ok() && shows_scene(image.value())) matching_png = png;
        }
        return !matching_png.empty();
      },
      std::chrono::seconds(60));
  EXPECT_TRUE(shown) << looked_at.size() << " PNG files, none shows the scene\n" << navview.log();

  navview.signal(SIGTERM);
  EXPECT_EQ(navview.wait(std::chrono::seconds(30)), 0) << navview.log();
  for (const auto& entry : std::filesystem::directory_iterator(out_dir)) {
    EXPECT_EQ(entry.path().extension(), ".png") << "left behind: " << entry.path();
  }
  if (!HasFailure()) std::filesystem::remove_all(out_dir);
}

TEST(NavviewHeadless, RefusesBadArgumentsAndAnUnwritableOutputDirectory) {
  ChildProcess usage({kNavview, "--headless", "--period-ms", "0"}, ::testing::TempDir() + "navview_usage.log");
  EXPECT_EQ(usage.wait(std::chrono::seconds(30)), 2);
  EXPECT_NE(usage.log().find("usage: navview"), std::string::npos) << usage.log();

  ChildProcess no_output({kNavview, "--headless", "--out-dir", "/proc/navview_cannot_be_here", "--domain", "163"},
                         ::testing::TempDir() + "navview_no_output.log");
  EXPECT_EQ(no_output.wait(std::chrono::seconds(30)), 1);
  EXPECT_NE(no_output.log().find("--out-dir"), std::string::npos) << no_output.log();
}

}  // namespace
}  // namespace nav::view
