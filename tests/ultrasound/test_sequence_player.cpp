// A PLUS recording played as an ultrasound device on DDS (loopback/shared memory only): the
// frames and probe poses arrive intact, in order, with the recorded intervals.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <memory>

#include "nav/dds/dds_node.hpp"
#include "nav/ultrasound/plus_sequence.hpp"
#include "nav/ultrasound/sequence_player.hpp"
#include "support/test_data.hpp"
#include "ultrasound_device_link.hpp"

namespace nav::ultrasound {
namespace {

TEST(SequencePlayer, PoseSampleIsTheRecordedTransformInMetres) {
  // 90 degrees about z, translation (10, 20, 30) mm.
  const Matrix4Mm matrix{0, -1, 0, 10, 1, 0, 0, 20, 0, 0, 1, 30, 0, 0, 0, 1};
  const dds::ToolPose pose = make_pose_sample(matrix, "ProbeToTracker", 2, 5, 77);
  EXPECT_NEAR(pose.position_m[1], 0.020, 1e-15);
  EXPECT_NEAR(pose.orientation_wxyz[0], std::sqrt(0.5), 1e-12);
  EXPECT_NEAR(pose.orientation_wxyz[3], std::sqrt(0.5), 1e-12);
  EXPECT_STREQ(pose.frame_from.data(), "probe");
  EXPECT_STREQ(pose.frame_to.data(), "tracker");
  EXPECT_EQ(pose.source_time_ns, 77);
}

TEST(SequencePlayer, RealRecordingReachesASubscriberAtRecordedTiming) {
  const std::string path = nav::testing::shared_data_path("plus/fCal_Test_Calibration_3NWires_fCal2.0.igs.mha");
  NAV_REQUIRE_SHARED_DATA(path);
  const auto sequence = read_plus_sequence(path, {.max_frames = 3});
  ASSERT_TRUE(sequence.ok()) << sequence.error().describe();
  testing::DeviceLink link = testing::link_device(141);
  ASSERT_TRUE(link.ok);

  SimulatedClock clock(kNsPerSecond);
  PlayOptions options;
  options.tools = {{"ProbeToTracker", 2}, {"ReferenceToTracker", 3}};
  const auto played = play_sequence(*link.device, sequence.value(), options, clock);
  ASSERT_TRUE(played.ok()) << played.error().describe();
  EXPECT_EQ(played.value(), 3u);
  ASSERT_TRUE(link.device->wait_for_acknowledgments(10 * kNsPerSecond));

  auto received = std::make_unique<dds::UltrasoundFrame>();
  std::vector<TimeNs> frame_times_ns;
  while (frame_times_ns.size() < 3 && testing::next_frame(link, *received)) {
    const std::size_t index = frame_times_ns.size();
    EXPECT_EQ(received->width_px, 820u);
    EXPECT_EQ(std::memcmp(received->pixels.data(), sequence.value().frame(index), 820 * 616), 0);
    frame_times_ns.push_back(received->source_time_ns);
  }
  ASSERT_EQ(frame_times_ns.size(), 3u);
  const auto& t = sequence.value().timestamps_s;
  EXPECT_NEAR(static_cast<double>(frame_times_ns[2] - frame_times_ns[0]) * 1e-9, t[2] - t[0], 1e-9);
  std::size_t probe_poses = 0;
  dds::ToolPose pose;
  while (link.poses->try_pop(pose)) {
    if (pose.tool_id != 2) continue;
    EXPECT_NEAR(pose.position_m[0],
                sequence.value().find_transform("ProbeToTracker")->matrices_mm[probe_poses][3] * 1e-3, 1e-12);
    ++probe_poses;
  }
  EXPECT_EQ(probe_poses, 3u);
}

TEST(SequencePlayer, UnknownTrackIsAnError) {
  dds::NetworkConfig network;
  network.domain_id = 142;
  auto node = dds::DdsNode::create(network);
  ASSERT_TRUE(node.ok());
  PlusSequence empty;
  SimulatedClock clock;
  const auto played = play_sequence(*node.value(), empty, PlayOptions{}, clock);
  ASSERT_FALSE(played.ok());
  EXPECT_EQ(played.error().field, "ProbeToTracker");
}

}  // namespace
}  // namespace nav::ultrasound
