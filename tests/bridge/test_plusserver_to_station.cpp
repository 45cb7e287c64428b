// A PLUS recording through OpenIGTLink to the station's topics, every hop a real one:
// `navdevice plusserver` (a process) serves PLUS's SpinePhantomFreehand recording as a
// PlusServer serves it, the bridge of the scene connects to it, and the station's side of DDS
// reads what arrives. Each pose and frame is compared with the recording read directly: the
// same poses (within float precision of OpenIGTLink's matrices), every frame's pixels and
// spacing, in the recorded order; and the latency of each hop chain, from the stamp the server
// gave a message as it sent it to the sample's arrival at the station's reader.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <fstream>
#include <map>
#include <memory>

#include "bridge_test_support.hpp"
#include "nav/dds/dds_node.hpp"
#include "nav/dds/sample_sink.hpp"
#include "nav/igtl/igtl_stream.hpp"
#include "nav/station/station_dds.hpp"
#include "nav/ultrasound/plus_sequence.hpp"
#include "nav/ultrasound/sequence_player.hpp"
#include "support/run_command.hpp"

namespace nav::testing {
namespace {

constexpr std::uint32_t kDomain = 223;

/// "median M ms, max X ms" of `latencies_ns` (sorted in place); the median and max in ms.
std::pair<double, double> median_and_max_ms(std::vector<TimeNs>& latencies_ns) {
  std::sort(latencies_ns.begin(), latencies_ns.end());
  if (latencies_ns.empty()) return {0.0, 0.0};
  return {1e-6 * static_cast<double>(latencies_ns[latencies_ns.size() / 2]),
          1e-6 * static_cast<double>(latencies_ns.back())};
}

/// A port free on loopback now (taken by a listener, then given back).
int free_port() {
  auto listener = igtl::Listener::listen({"127.0.0.1", 0});
  return listener.ok() ? listener.value().port() : 0;
}

TEST(PlusServerToStation, APlusRecordingArrivesOnTheStationsTopicsAsRecorded) {
  const std::string recording = shared_data_path("plus/SpinePhantomFreehand.igs.mha");
  NAV_REQUIRE_SHARED_DATA(recording);
  auto expected = ultrasound::read_plus_sequence(recording);
  ASSERT_TRUE(expected.ok()) << expected.error().describe();
  const ultrasound::PlusSequence& q = expected.value();
  const int port = free_port();
  ASSERT_GT(port, 0);
  const std::string text = edited(movable_demo_text(), "domain_id: 0", "domain_id: " + std::to_string(kDomain)) +
                           "\nopenigtlink:\n  plus: {connect: 127.0.0.1:" + std::to_string(port) +
                           "}\n  image: Image_Reference\n  displays: 127.0.0.1:0\n";
  const std::string scene_path = temporary_path("plusserver.yaml");
  std::ofstream(scene_path) << text;
  const station::Scene scene = bridge_scene(kDomain, text.substr(text.find("openigtlink:\n") + 13));

  auto station_node =
      station::make_station_node(kDomain, "test_station", station::topic_names(scene.topics), scene.network);
  ASSERT_TRUE(station_node.ok());
  auto poses = std::make_unique<dds::RingSink<dds::ToolPose, 128>>();
  auto frames = std::make_unique<dds::RingSink<dds::UltrasoundFrame, 32>>();
  ASSERT_TRUE(station_node.value()->subscribe(*poses).ok());
  ASSERT_TRUE(station_node.value()->subscribe(*frames).ok());
  auto bridge = bridge::IgtlBridge::open(scene);
  ASSERT_TRUE(bridge.ok()) << bridge.error().describe();
  const RunningBridge running(*bridge.value());
  ASSERT_TRUE(station_node.value()->wait_for_match(dds::Topic::ultrasound_frame, 1, 10 * kNsPerSecond));

  const CommandRun served = run_command(executable_path("navdevice") + " plusserver --scene " + scene_path +
                                        " --recording " + recording + " --wait-s 20 2>&1");
  std::printf("%s", served.output.c_str());
  ASSERT_EQ(served.exit_code, 0);

  std::size_t valid_poses = 0, valid_frames = 0;
  for (const char* name : {"ProbeToTracker", "StylusToTracker"})
    for (const std::uint8_t v : q.find_transform(name)->valid) valid_poses += v;
  for (const std::uint8_t v : q.image_valid) valid_frames += v;
  ASSERT_TRUE(wait_until([&] { return frames->size() == valid_frames && poses->size() == valid_poses; }))
      << frames->size() << " of " << valid_frames << " frames, " << poses->size() << " of " << valid_poses << " poses";

  // The poses of each tool in the recorded order, against the recording's own matrices.
  std::map<std::uint32_t, std::size_t> next_index;  // tool id -> next recorded frame to compare with
  const std::map<std::uint32_t, const ultrasound::TransformTrack*> track_of{
      {scene.devices.tracker.tools.probe, q.find_transform("ProbeToTracker")},
      {scene.devices.tracker.tools.needle, q.find_transform("StylusToTracker")}};
  double worst_mm = 0.0, worst_rad = 0.0;
  std::vector<TimeNs> pose_latency_ns, frame_latency_ns;
  for (dds::ToolPose pose; poses->try_pop(pose);) {
    pose_latency_ns.push_back(pose.receive_time_ns - pose.source_time_ns);
    const ultrasound::TransformTrack& track = *track_of.at(pose.tool_id);
    std::size_t& i = next_index[pose.tool_id];
    while (track.valid[i] == 0) ++i;
    const dds::ToolPose recorded = ultrasound::make_pose_sample(track.matrices_mm[i], track.name, 0, i, 0);
    ++i;
    for (std::size_t k = 0; k < 3; ++k)
      worst_mm = std::max(worst_mm, 1e3 * std::abs(pose.position_m[k] - recorded.position_m[k]));
    const Eigen::Quaterniond a(pose.orientation_wxyz[0], pose.orientation_wxyz[1], pose.orientation_wxyz[2],
                               pose.orientation_wxyz[3]);
    const Eigen::Quaterniond b(recorded.orientation_wxyz[0], recorded.orientation_wxyz[1], recorded.orientation_wxyz[2],
                               recorded.orientation_wxyz[3]);
    worst_rad = std::max(worst_rad, a.angularDistance(b));
  }
  std::printf("%zu poses, %zu frames; worst position %.2e mm, worst rotation %.2e rad\n", valid_poses, valid_frames,
              worst_mm, worst_rad);
  EXPECT_LT(worst_mm, 1e-3);  // float matrices on the wire: about 1e-5 mm at these distances
  EXPECT_LT(worst_rad, 1e-5);

  std::size_t index = 0;
  for (auto frame = std::make_unique<dds::UltrasoundFrame>(); frames->try_pop(*frame); ++index) {
    while (q.image_valid[index] == 0) ++index;
    frame_latency_ns.push_back(frame->receive_time_ns - frame->source_time_ns);
    ASSERT_EQ(frame->width_px, q.width_px);
    ASSERT_EQ(frame->height_px, q.height_px);
    EXPECT_NEAR(frame->pixel_spacing_m[0], 1e-3 * q.spacing_mm[0], 1e-9);
    EXPECT_EQ(frame->probe_tool_id, scene.devices.tracker.tools.probe);
    EXPECT_TRUE(std::equal(q.frame(index), q.frame(index) + q.frame_pixels(), frame->pixels.begin()))
        << "frame " << index;
  }
  EXPECT_EQ(bridge.value()->totals().refused_in, 0u);
  // Sent, read by the bridge, restamped, written to DDS and read: loopback and shared memory.
  const auto [pose_median_ms, pose_max_ms] = median_and_max_ms(pose_latency_ns);
  const auto [frame_median_ms, frame_max_ms] = median_and_max_ms(frame_latency_ns);
  std::printf(
      "server to station reader: poses median %.2f ms, max %.2f ms; frames (%u x %u) median %.2f ms, max %.2f ms\n",
      pose_median_ms, pose_max_ms, q.width_px, q.height_px, frame_median_ms, frame_max_ms);
  EXPECT_GT(pose_median_ms, -1.0);  // a stamp is never much after its arrival (the clocks read apart by microseconds)
  EXPECT_LT(pose_median_ms, 50.0);  // generous: sanitizers and a loaded host
  EXPECT_LT(frame_median_ms, 100.0);
  EXPECT_LT(std::max(pose_max_ms, frame_max_ms), 1000.0);
}

}  // namespace
}  // namespace nav::testing
