// A recorded session replayed through the station meets the live station's boundary: in a
// recording of the demo's three tools at 60 Hz for 2 s, a pose stamped 1e6 s ahead, a pose
// 1e300 m away, a pose of a tool the scene does not know and a pose older than its tool's
// previous one are refused, each for its reason, and every legitimate pose after them is
// still taken (a future stamp does not blind the stream). The replay runs on all of them, and
// twice to the same output hash.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "nav/dds/recording_file.hpp"
#include "nav/dds/sample_codec.hpp"
#include "nav/station/session_replay.hpp"
#include "scene_text.hpp"

namespace nav::station {
namespace {

constexpr TimeNs kRecordingStartNs = 1'000 * kNsPerSecond;  // the recording host's monotonic clock
constexpr TimeNs kPoseLatencyNs = 5 * kNsPerMs;             // from a pose's measurement to its arrival
constexpr int kTicks = 120;                                 // 2 s at 60 Hz

dds::ToolPose pose_of(std::uint32_t tool, TimeNs source_ns, double x_m) {
  dds::ToolPose pose;
  pose.tool_id = tool;
  pose.source_time_ns = source_ns;
  pose.position_m = {x_m, 0.1, 0.05};
  pose.quality = 1.0f;
  return pose;
}

void append(dds::RecordingWriter& writer, const dds::ToolPose& pose, TimeNs receive_ns) {
  std::vector<std::uint8_t> bytes;
  ASSERT_TRUE(dds::encode_sample(pose, bytes));
  ASSERT_TRUE(writer.append(dds::Topic::tool_pose, pose.source_time_ns, receive_ns, bytes).ok());
}

/// The recording: the three tools every tick, and the four hostile poses among them.
std::string hostile_recording() {
  const std::string path = testing::temporary_path("hostile_session.navrec");
  auto writer = dds::RecordingWriter::create(path);
  EXPECT_TRUE(writer.ok()) << writer.error().describe();
  for (int k = 0; k < kTicks; ++k) {
    const TimeNs measured_ns = kRecordingStartNs + k * kNsPerSecond / 60;
    const TimeNs arrival_ns = measured_ns + kPoseLatencyNs;
    for (const std::uint32_t tool : {1u, 2u, 3u})
      append(*writer.value(), pose_of(tool, measured_ns, 0.001 * k), arrival_ns);
    if (k == 10)
      append(*writer.value(), pose_of(1, measured_ns + 1'000'000 * kNsPerSecond, 0.0), arrival_ns);  // 1e6 s ahead
    if (k == 20) append(*writer.value(), pose_of(2, measured_ns + 1, 1e300), arrival_ns);            // 1e300 m away
    if (k == 30) append(*writer.value(), pose_of(7, measured_ns, 0.0), arrival_ns);                  // no such tool
    if (k == 40)
      append(*writer.value(), pose_of(3, measured_ns - 10 * kNsPerMs, 0.0), arrival_ns);  // older than tool 3's last
  }
  EXPECT_TRUE(writer.value()->close().ok());
  return path;
}

TEST(SessionReplay, RecordedPosesMeetTheLiveBoundaryAndTheRestIsTaken) {
  const auto scene = load_scene(testing::example_scene_path("demo.yaml"));
  ASSERT_TRUE(scene.ok()) << scene.error().describe();
  const std::string recording = hostile_recording();
  const auto replay = replay_session(scene.value(), recording);
  ASSERT_TRUE(replay.ok()) << replay.error().describe();
  const SessionReplay& r = replay.value();
  EXPECT_EQ(r.boundary.time_out_of_window, 1u);
  EXPECT_EQ(r.boundary.implausible_pose, 1u);
  EXPECT_EQ(r.boundary.unknown_tool, 1u);
  EXPECT_EQ(r.boundary.time_backwards, 1u);
  EXPECT_EQ(r.records_refused, 4);
  EXPECT_EQ(r.poses, 3 * kTicks);  // every legitimate pose, also the needle's after the future stamp
  EXPECT_EQ(r.boundary.accepted, static_cast<std::uint64_t>(3 * kTicks));
  const std::string text = format_replay(scene.value(), recording, r);
  EXPECT_NE(text.find("refused at the station's boundary: "), std::string::npos) << text;
  EXPECT_NE(text.find("time_out_of_window 1"), std::string::npos) << text;
  const auto again = replay_session(scene.value(), recording);
  ASSERT_TRUE(again.ok());
  EXPECT_EQ(again.value().replay.output_hash, r.replay.output_hash);
}

}  // namespace
}  // namespace nav::station
