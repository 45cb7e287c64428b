// DDS Security as a scene turns it on: `navtool security init` makes a CA and the identities of
// the station's roles, every participant of the scene joins with its role's certificate and
// permissions, and participants without them, with another CA's, or beyond their permissions
// can neither read the station's predictions nor put a pose into it.
#include <gtest/gtest.h>

#include <atomic>
#include <filesystem>
#include <memory>
#include <vector>

#include "nav/dds/dds_node.hpp"
#include "nav/station/security_roles.hpp"
#include "nav/station/station_build.hpp"
#include "nav/station/station_dds.hpp"
#include "station/scene_text.hpp"
#include "support/run_command.hpp"
#include "support/test_data.hpp"

namespace nav::station {
namespace {

constexpr std::uint32_t kDomain = 211;
constexpr std::uint32_t kDeviceTool = 1;     // the tool id the legitimate device writes
constexpr std::uint32_t kIntruderTool = 66;  // the tool id every intruder writes

/// A folder of `navtool security init` (made once per folder and test program).
std::string initialised_folder(const std::string& name) {
  const std::string dir = testing::temporary_path(name);
  if (!std::filesystem::exists(std::filesystem::path(dir) / "tool" / "permissions.p7s")) {
    const auto made = testing::run_command(testing::executable_path("navtool") + " security init " + dir + " 2>&1");
    EXPECT_EQ(made.exit_code, 0) << made.output;
  }
  return dir;
}

/// The scene's network with a `security:` section on the files of `dir`, by `{role}`.
NetworkSettings secured(const std::string& dir) {
  NetworkSettings network;
  network.security = security_folder(dir);
  return network;
}

/// Counts the poses it is offered, by whether they come from the device or an intruder.
class PoseCounter final : public dds::SampleSink<dds::ToolPose> {
 public:
  dds::SampleFault offer(const dds::ToolPose& pose) noexcept override {
    (pose.tool_id == kIntruderTool ? intruder : device).fetch_add(1);
    return dds::SampleFault::none;
  }
  std::atomic<int> device{0}, intruder{0};
};

/// Counts the predictions it is offered.
class PredictionCounter final : public dds::SampleSink<dds::TargetPrediction> {
 public:
  dds::SampleFault offer(const dds::TargetPrediction&) noexcept override {
    count.fetch_add(1);
    return dds::SampleFault::none;
  }
  std::atomic<int> count{0};
};

dds::ToolPose pose_of(std::uint32_t tool_id, std::uint64_t sequence) {
  dds::ToolPose pose;
  pose.tool_id = tool_id;
  pose.sequence_number = sequence;
  pose.source_time_ns = MonotonicClock().now_ns();
  pose.quality = 1.0f;
  return pose;
}

dds::TargetPrediction prediction_of(std::uint64_t i) {
  dds::TargetPrediction prediction;
  prediction.source_time_ns = MonotonicClock().now_ns();
  prediction.position_m = {0.01 * static_cast<double>(i % 7), 0.0, 0.0};
  return prediction;
}

/// A participant of `role` on `network`, which must be created.
std::unique_ptr<dds::DdsNode> joined(const char* name, const NetworkSettings& network, Role role) {
  auto node = make_station_node(kDomain, name, {}, network, role);
  EXPECT_TRUE(node.ok()) << name << ": " << (node.ok() ? "" : node.error().describe());
  return node.ok() ? std::move(node).value() : nullptr;
}

TEST(StationSecurity, OnlyTheScenesIdentitiesReadPredictionsAndOnlyItsDevicesWritePoses) {
  const NetworkSettings scene = secured(initialised_folder("security_keys"));
  const NetworkSettings other_ca = secured(initialised_folder("security_keys_of_another_ca"));

  auto poses = std::make_unique<PoseCounter>();
  auto display_predictions = std::make_unique<PredictionCounter>();
  auto station = joined("station", scene, Role::station);
  auto device = joined("device", scene, Role::devices);
  auto display = joined("display", scene, Role::display);
  ASSERT_TRUE(station && device && display);
  ASSERT_TRUE(station->subscribe(*poses).ok());
  ASSERT_TRUE(station->advertise<dds::TargetPrediction>().ok());
  ASSERT_TRUE(device->advertise<dds::ToolPose>().ok());
  ASSERT_TRUE(display->subscribe(*display_predictions).ok());

  // Intruders, each trying to inject poses and to read the predictions:
  // no certificate at all, and a certificate of another CA (with that CA's governance).
  struct Intruder {
    const char* what;
    std::unique_ptr<dds::DdsNode> node;
    std::unique_ptr<PredictionCounter> predictions = std::make_unique<PredictionCounter>();
  };
  Intruder intruders[] = {{"no certificate", joined("intruder_plain", NetworkSettings{}, Role::devices)},
                          {"another CA's certificate", joined("intruder_foreign", other_ca, Role::tool)}};
  for (Intruder& intruder : intruders) {
    ASSERT_TRUE(intruder.node) << intruder.what;
    ASSERT_TRUE(intruder.node->advertise<dds::ToolPose>().ok()) << intruder.what;
    ASSERT_TRUE(intruder.node->subscribe(*intruder.predictions).ok()) << intruder.what;
  }
  // Our CA's identities beyond their permissions: a display may not write poses and a device
  // may not read predictions (refused at creation, before anything reaches the wire).
  EXPECT_FALSE(display->advertise<dds::ToolPose>().ok());
  auto device_predictions = std::make_unique<PredictionCounter>();
  EXPECT_FALSE(device->subscribe(*device_predictions).ok());

  ASSERT_TRUE(station->wait_for_match(dds::Topic::tool_pose, 1, 20 * kNsPerSecond))
      << "the device never matched the station";
  ASSERT_TRUE(station->wait_for_match(dds::Topic::target_prediction, 1, 20 * kNsPerSecond))
      << "the display never matched";
  // Two seconds of traffic, then time for the last samples to land.
  MonotonicClock clock;
  for (std::uint64_t i = 0; i < 400; ++i) {
    device->write(pose_of(kDeviceTool, i));
    for (Intruder& intruder : intruders) intruder.node->write(pose_of(kIntruderTool, i));
    station->write(prediction_of(i));
    clock.sleep_until_ns(clock.now_ns() + 5 * kNsPerMs);
  }
  clock.sleep_until_ns(clock.now_ns() + kNsPerSecond);

  EXPECT_GE(poses->device.load(), 300) << "the device's poses reach the station";
  EXPECT_EQ(poses->intruder.load(), 0) << "no intruder's pose reaches the station";
  EXPECT_GE(display_predictions->count.load(), 300) << "the display reads the predictions";
  for (const Intruder& intruder : intruders)
    EXPECT_EQ(intruder.predictions->count.load(), 0) << intruder.what << " read predictions";
  // The station sees exactly one writer of poses (the device) and one reader of predictions.
  EXPECT_EQ(station->matched(dds::Topic::tool_pose), 1u);
  EXPECT_EQ(station->matched(dds::Topic::target_prediction), 1u);
}

TEST(StationSecurity, AnIdentityPresentingAnotherRolesPermissionsCannotJoin) {
  // The display's certificate with the tool's permissions (signed for the subject CN=tool).
  NetworkSettings borrowed = secured(initialised_folder("security_keys"));
  borrowed.security.permissions =
      borrowed.security.permissions.replace(borrowed.security.permissions.find("{role}"), 6, "tool");
  EXPECT_FALSE(make_station_node(kDomain + 1, "borrowed_permissions", {}, borrowed, Role::display).ok());
  EXPECT_TRUE(
      make_station_node(kDomain + 1, "own_permissions", {}, secured(initialised_folder("security_keys")), Role::display)
          .ok());
}

TEST(StationSecurity, SecurityInitRefusesWhatItCannotUse) {
  const std::string navtool = testing::executable_path("navtool") + " security init ";
  // No folder, a bad or out-of-range --days, an unknown flag: usage errors, nothing made.
  for (const std::string& args : std::vector<std::string>{
           "", "--days 30", testing::temporary_path("k1") + " --days zero", testing::temporary_path("k2") + " --days 0",
           testing::temporary_path("k3") + " --bits 4096"}) {
    const auto run = testing::run_command(navtool + args + " 2>&1");
    EXPECT_EQ(run.exit_code, 2) << args << ": " << run.output;
    EXPECT_NE(run.output.find("usage: navtool security init DIR"), std::string::npos) << run.output;
  }
  EXPECT_FALSE(std::filesystem::exists(testing::temporary_path("k2")));
  // A scene that does not load is named; a folder that cannot be made is named.
  const auto bad_scene =
      testing::run_command(navtool + testing::temporary_path("k4") + " --scene /no/such/scene.yaml 2>&1");
  EXPECT_EQ(bad_scene.exit_code, 2);
  EXPECT_NE(bad_scene.output.find("/no/such/scene.yaml"), std::string::npos) << bad_scene.output;
  const auto bad_folder = testing::run_command(navtool + "/proc/no_keys_here 2>&1");
  EXPECT_EQ(bad_folder.exit_code, 1);
  EXPECT_NE(bad_folder.output.find("/proc/no_keys_here"), std::string::npos) << bad_folder.output;
}

TEST(StationSecurity, AMissingFileIsNamedByItsSceneKeyAndNoUnsecuredParticipantIsMade) {
  NetworkSettings scene = secured(initialised_folder("security_keys"));
  scene.security.private_key = testing::temporary_path("no_such_key.pem");
  const auto node = make_station_node(kDomain + 1, "station", {}, scene, Role::station);
  ASSERT_FALSE(node.ok());
  EXPECT_EQ(node.error().field, "security.private_key");
  EXPECT_EQ(node.error().file, scene.security.private_key);
  scene.security.private_key.clear();
  const auto partial = make_station_node(kDomain + 1, "station", {}, scene, Role::station);
  ASSERT_FALSE(partial.ok());
  EXPECT_EQ(partial.error().field, "security.private_key");
}

TEST(StationSecurity, TheScenesSectionGivesEachRoleItsOwnFilesAndTheStationChecksItsOwn) {
  const std::string section =
      "security:\n  ca: keys/ca.pem\n  certificate: keys/{role}/certificate.pem\n  private_key: "
      "/etc/navrt/{role}/key.pem\n"
      "  governance: keys/governance.p7s\n  permissions: keys/{role}/permissions.p7s\n";
  const std::string path = testing::example_scene_path("demo.yaml");
  const std::string folder = std::filesystem::path(path).parent_path().lexically_normal().string();
  const auto scene = parse_scene(testing::demo_text() + section, path);
  ASSERT_TRUE(scene.ok()) << scene.error().describe();
  const SecuritySettings& s = scene.value().network.security;
  EXPECT_EQ(s.line, testing::line_of(testing::demo_text() + section, "security:") + 1);
  const dds::SecurityFiles display = security_files(s, Role::display);
  EXPECT_EQ(display.ca, folder + "/keys/ca.pem");  // relative to the scene's folder
  EXPECT_EQ(display.certificate, folder + "/keys/display/certificate.pem");
  EXPECT_EQ(display.private_key, "/etc/navrt/display/key.pem");
  EXPECT_EQ(security_files(s, Role::devices).permissions, folder + "/keys/devices/permissions.p7s");
  EXPECT_FALSE(security_files(load_scene(path).value().network.security, Role::station).enabled());  // no section: off

  // A key left out is named; the station's own missing file stops the build before any model.
  const auto partial =
      parse_scene(testing::demo_text() + testing::edited(section, "  governance: keys/governance.p7s\n", ""), path);
  ASSERT_FALSE(partial.ok());
  EXPECT_EQ(partial.error().field, "security.governance") << partial.error().describe();
  const auto built = build_station(scene.value());
  ASSERT_FALSE(built.ok());
  EXPECT_EQ(built.error().file, path);
  EXPECT_EQ(built.error().line, s.line);
  EXPECT_EQ(built.error().field, "security.ca") << built.error().describe();
  EXPECT_NE(built.error().message.find(folder + "/keys/ca.pem"), std::string::npos) << built.error().describe();
}

}  // namespace
}  // namespace nav::station
