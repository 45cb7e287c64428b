// navdevice apriltag, a camera on tag36h11 markers as a device process: an image sequence of
// rendered tags (tag 0 the needle's, moving 1 cm a frame; tag 1 the probe's, tilted; the
// respiratory marker's tag out of view) with the scene's intrinsics file (navtool calib
// camera's format) and tag size: each tool's pose reaches a station's reader in the camera's
// frame within 2 mm of where it was rendered, the unseen tool is counted, not published. A
// needle carrying two tags (devices.tracker.bodies) is solved on both, and on the one left
// when the other leaves the view. A scene without intrinsics, or a bad intrinsics file, is
// refused naming the key or the line; so are a tag on two tools and a body of no tags.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>

#include "dds/child_process.hpp"
#include "dds/station_stand_in.hpp"
#include "nav/trackers/apriltag_tracker.hpp"
#include "nav/trackers/gray_image.hpp"
#include "station/scene_text.hpp"
#include "support/test_data.hpp"

namespace nav::testing {
namespace {

const std::string kBin = NAV_BIN_DIR;
constexpr int kFrames = 6;
constexpr double kTagSizeM = 0.03;

Eigen::Isometry3d needle_at(int frame) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(-0.03 + 0.01 * frame, 0.0, 0.4);
  return pose;
}

Eigen::Isometry3d probe_pose() {
  Eigen::Isometry3d pose(Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitX()));
  pose.translation() = Eigen::Vector3d(0.0, 0.06, 0.45);
  return pose;
}

/// The tags seen in frame i.
using TagsOfFrame = std::vector<trackers::TagRendering> (*)(int frame);

std::vector<trackers::TagRendering> needle_and_probe_tags(int frame) {
  return {{0, needle_at(frame)}, {1, probe_pose()}};
}

/// The needle's two-tag body: tag 0 left of the tool's origin, tag 3 right of it and turned.
Eigen::Isometry3d needle_from_tag(int id) {
  Eigen::Isometry3d pose(Eigen::AngleAxisd(id == 3 ? 0.3 : 0.0, Eigen::Vector3d::UnitY()));
  pose.translation() = Eigen::Vector3d(id == 3 ? 0.025 : -0.025, 0.0, 0.0);
  return pose;
}

/// The needle body turned about the camera's axis a little more each frame; from frame 4 on
/// its tag 3 is out of view.
Eigen::Isometry3d body_at(int frame) {
  return needle_at(frame) * Eigen::AngleAxisd(0.1 * frame, Eigen::Vector3d::UnitZ());
}

std::vector<trackers::TagRendering> body_and_probe_tags(int frame) {
  std::vector<trackers::TagRendering> tags{{0, body_at(frame) * needle_from_tag(0)}, {1, probe_pose()}};
  if (frame < 4) tags.push_back({3, body_at(frame) * needle_from_tag(3)});
  return tags;
}

/// The rendered sequence (frame_000.pgm ...) and its intrinsics file; returns the pattern.
std::string write_tag_sequence(const std::string& intrinsics_path, const std::string& name = "apriltag_sequence",
                               TagsOfFrame tags_of = needle_and_probe_tags) {
  const trackers::CameraIntrinsics camera;  // 600 px focal length, 640 x 480
  std::ofstream(intrinsics_path) << "# fx_px fy_px cx_px cy_px k1 k2 p1 p2 k3 rms_px\n"
                                 << camera.fx_px << " " << camera.fy_px << " " << camera.cx_px << " " << camera.cy_px
                                 << " 0 0 0 0 0 0.1\n";
  const std::filesystem::path folder = temporary_path(name);
  std::filesystem::create_directories(folder);
  for (int i = 0; i < kFrames; ++i) {
    char file[32];
    std::snprintf(file, sizeof file, "frame_%03d.pgm", i);
    const trackers::GrayImage image = trackers::render_tags(tags_of(i), kTagSizeM, camera, 640, 480, 1.0, 40 + i);
    EXPECT_TRUE(trackers::write_pgm((folder / file).string(), image).ok());
  }
  return (folder / "frame_%03d.pgm").string();
}

/// The demo scene with an AprilTag tracker on `tracker` lines (camera, intrinsics, ...).
std::string apriltag_scene(const std::string& tracker) {
  const std::string simulated =
      "    kind: simulated\n    rate_hz: 60\n    latency_ms: 10\n    position_noise_m: 0.00025\n    "
      "rotation_noise_rad: 0.001\n    seed: 1\n";
  const std::string path = temporary_path("apriltag_scene.yaml");
  std::ofstream(path) << edited(
      movable_demo_text(), simulated,
      "    kind: apriltag\n" + tracker + "    tools: {needle: 11, probe: 12, respiratory: 13}\n");
  return path;
}

double distance_m(const dds::ToolPose& pose, const Eigen::Vector3d& truth) {
  return (Eigen::Vector3d(pose.position_m[0], pose.position_m[1], pose.position_m[2]) - truth).norm();
}

TEST(NavdeviceApriltag, EachToolsTagReachesTheStationWhereItWasRendered) {
  const std::string intrinsics = temporary_path("camera.txt");
  const std::string scene = apriltag_scene("    camera: " + write_tag_sequence(intrinsics) +
                                           "\n    tag_size_m: 0.03\n    intrinsics: " + intrinsics +
                                           "\n    tags: {needle: 0, probe: 1, respiratory: 2}\n    rate_hz: 20\n");
  StationStandIn<dds::ToolPose, 64> station(184);
  ChildProcess device({kBin + "/navdevice", "apriltag", "--scene", scene, "--domain", "184"},
                      temporary_path("navdevice_apriltag.log"));
  ASSERT_TRUE(device.started());
  const auto received =
      station.collect([](const auto& received) { return received.size() >= 2 * kFrames; }, std::chrono::seconds(60));
  ASSERT_EQ(device.wait(std::chrono::seconds(30)), 0) << device.log();
  std::printf("%s", device.log().c_str());
  std::map<std::uint32_t, std::vector<const dds::ToolPose*>> by_tool;
  for (const auto& pose : received) by_tool[pose->tool_id].push_back(pose.get());
  ASSERT_EQ(by_tool[11].size(), static_cast<std::size_t>(kFrames));
  ASSERT_EQ(by_tool[12].size(), static_cast<std::size_t>(kFrames));
  EXPECT_EQ(by_tool.count(13), 0u);  // the respiratory marker's tag is not in view
  for (int i = 0; i < kFrames; ++i) {
    EXPECT_LT(distance_m(*by_tool[11][static_cast<std::size_t>(i)], needle_at(i).translation()), 2e-3) << "frame " << i;
    EXPECT_LT(distance_m(*by_tool[12][static_cast<std::size_t>(i)], probe_pose().translation()), 2e-3) << "frame " << i;
  }
  EXPECT_STREQ(by_tool[11].front()->frame_from.data(), "needle_marker");
  EXPECT_STREQ(by_tool[11].front()->frame_to.data(), "camera");
  const std::string log = device.log();
  const std::size_t end = log.find("end of the stream after");
  ASSERT_NE(end, std::string::npos);
  EXPECT_EQ(number_after(log.substr(end), "poses published, "),
            static_cast<double>(kFrames));  // without a pose: the respiratory marker
}

double angle_rad(const dds::ToolPose& pose, const Eigen::Isometry3d& truth) {
  const Eigen::Quaterniond q(pose.orientation_wxyz[0], pose.orientation_wxyz[1], pose.orientation_wxyz[2],
                             pose.orientation_wxyz[3]);
  return q.angularDistance(Eigen::Quaterniond(truth.rotation()));
}

/// devices.tracker.bodies: the needle on tags 0 and 3 at their poses on it.
const std::string kNeedleBody =
    "    bodies:\n"
    "      needle:\n"
    "        - {id: 0, xyz: [-0.025, 0, 0], rpy: [0, 0, 0]}\n"
    "        - {id: 3, xyz: [0.025, 0, 0], rpy: [0, 0.3, 0]}\n";

TEST(NavdeviceApriltag, AToolOnSeveralTagsIsSolvedOnThoseInView) {
  const std::string intrinsics = temporary_path("camera_body.txt");
  const std::string pattern = write_tag_sequence(intrinsics, "apriltag_body_sequence", body_and_probe_tags);
  const std::string scene =
      apriltag_scene("    camera: " + pattern + "\n    tag_size_m: 0.03\n    intrinsics: " + intrinsics +
                     "\n    tags: {needle: 5, probe: 1, respiratory: 2}\n" + kNeedleBody + "    rate_hz: 20\n");
  StationStandIn<dds::ToolPose, 64> station(185);
  ChildProcess device({kBin + "/navdevice", "apriltag", "--scene", scene, "--domain", "185"},
                      temporary_path("navdevice_apriltag_body.log"));
  ASSERT_TRUE(device.started());
  const auto received =
      station.collect([](const auto& received) { return received.size() >= 2 * kFrames; }, std::chrono::seconds(60));
  ASSERT_EQ(device.wait(std::chrono::seconds(30)), 0) << device.log();
  std::printf("%s", device.log().c_str());
  EXPECT_NE(device.log().find("tags 0+3 the needle (tool 11)"), std::string::npos);
  std::vector<const dds::ToolPose*> needle;
  for (const auto& pose : received)
    if (pose->tool_id == 11) needle.push_back(pose.get());
  ASSERT_EQ(needle.size(), static_cast<std::size_t>(kFrames));
  for (int i = 0; i < kFrames; ++i) {
    const dds::ToolPose& pose = *needle[static_cast<std::size_t>(i)];
    EXPECT_LT(distance_m(pose, body_at(i).translation()), 2e-3)
        << "frame " << i;  // the tool's origin lies between its tags
    EXPECT_LT(angle_rad(pose, body_at(i)), 0.02) << "frame " << i;
  }
}

TEST(NavdeviceApriltag, NamesWhatIsMissing) {
  ChildProcess no_intrinsics({kBin + "/navdevice", "apriltag", "--scene",
                              apriltag_scene("    camera: 0\n    tag_size_m: 0.03\n"), "--no-wait"},
                             temporary_path("navdevice_apriltag_no_intrinsics.log"));
  EXPECT_EQ(no_intrinsics.wait(std::chrono::seconds(30)), 1);
  EXPECT_NE(no_intrinsics.log().find("devices.tracker.intrinsics is required"), std::string::npos)
      << no_intrinsics.log();
  const std::string bad = temporary_path("bad_camera.txt");
  std::ofstream(bad) << "# fx_px fy_px cx_px cy_px k1 k2 p1 p2 k3 rms_px\n600 600 319.5\n";
  ChildProcess bad_file(
      {kBin + "/navdevice", "apriltag", "--scene",
       apriltag_scene("    camera: 0\n    tag_size_m: 0.03\n    intrinsics: " + bad + "\n"), "--no-wait"},
      temporary_path("navdevice_apriltag_bad.log"));
  EXPECT_EQ(bad_file.wait(std::chrono::seconds(30)), 1);
  EXPECT_NE(bad_file.log().find(bad + ":2:"), std::string::npos) << bad_file.log();
  ChildProcess simulated({kBin + "/navdevice", "apriltag", "--scene", example_scene_path("demo.yaml"), "--no-wait"},
                         temporary_path("navdevice_apriltag_simulated.log"));
  EXPECT_EQ(simulated.wait(std::chrono::seconds(30)), 1);
  EXPECT_NE(simulated.log().find("not an AprilTag tracker"), std::string::npos) << simulated.log();
  // A body's tag already another tool's (the probe's tag 1), and a body of no tags.
  ChildProcess shared(
      {kBin + "/navdevice", "apriltag", "--scene",
       apriltag_scene("    camera: 0\n    tag_size_m: 0.03\n" + edited(kNeedleBody, "id: 3", "id: 1")), "--no-wait"},
      temporary_path("navdevice_apriltag_shared.log"));
  EXPECT_EQ(shared.wait(std::chrono::seconds(30)), 1);
  EXPECT_NE(shared.log().find("devices.tracker.bodies: tag 1 is on two tools (needle and probe)"), std::string::npos)
      << shared.log();
  ChildProcess empty({kBin + "/navdevice", "apriltag", "--scene",
                      apriltag_scene("    camera: 0\n    tag_size_m: 0.03\n    bodies: {needle: []}\n"), "--no-wait"},
                     temporary_path("navdevice_apriltag_empty_body.log"));
  EXPECT_EQ(empty.wait(std::chrono::seconds(30)), 1);
  EXPECT_NE(empty.log().find("devices.tracker.bodies.needle"), std::string::npos) << empty.log();
}

}  // namespace
}  // namespace nav::testing
