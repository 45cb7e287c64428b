// Every station topic end to end through DDS in one process: poses into the per-tool
// inbox, 1 MiB frames into a ring, the core's outputs from the outbox to a display's sinks;
// and bad samples of each kind dropped at the boundary, counted, and published in health.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "dds_test_samples.hpp"
#include "nav/core/health.hpp"
#include "nav/dds/dds_node.hpp"
#include "nav/dds/pose_inbox.hpp"
#include "nav/dds/station_outbox.hpp"
#include "nav/dds/topic_qos.hpp"

namespace nav::dds {
namespace {

using namespace testing;
constexpr TimeNs kMatchTimeoutNs = 10 * kNsPerSecond;

/// A publishing node and a subscribing node on one domain.
struct NodePair {
  std::unique_ptr<DdsNode> writer;
  std::unique_ptr<DdsNode> reader;
};

NodePair make_pair(std::uint32_t domain_id) {
  auto writer = DdsNode::create(local_network(domain_id));
  auto reader = DdsNode::create(local_network(domain_id));
  EXPECT_TRUE(writer.ok() && reader.ok());
  return {std::move(writer).value(), std::move(reader).value()};
}

TEST(DdsPubSub, PosesReachThePoseInboxStampedAndIntact) {
  NodePair nodes = make_pair(101);
  PoseInbox inbox{1, 2};
  ASSERT_TRUE(nodes.writer->advertise<ToolPose>().ok());
  ASSERT_TRUE(nodes.reader->subscribe(inbox).ok());
  ASSERT_TRUE(nodes.writer->wait_for_match(Topic::tool_pose, 1, kMatchTimeoutNs));
  const MonotonicClock clock;
  TimeNs sent_ns = 0;
  ASSERT_TRUE(wait_until([&] {
    sent_ns = clock.now_ns();
    nodes.writer->write(make_pose(2, sent_ns));
    return inbox.update(1);
  }));
  const ToolPose& pose = inbox.latest(1);
  EXPECT_EQ(pose.tool_id, 2u);
  EXPECT_EQ(pose.orientation_wxyz, make_pose(2, 0).orientation_wxyz);
  EXPECT_GE(pose.receive_time_ns, pose.source_time_ns);
  EXPECT_FALSE(inbox.update(0));  // tool 1 never sent
  EXPECT_EQ(nodes.reader->boundary_counts().non_finite, 0u);
}

TEST(DdsPubSub, FullSizeFramesReachTheFrameRing) {
  NodePair nodes = make_pair(102);
  auto ring = std::make_unique<RingSink<UltrasoundFrame, 4>>();
  ASSERT_TRUE(nodes.writer->advertise<UltrasoundFrame>().ok());
  ASSERT_TRUE(nodes.reader->subscribe(*ring).ok());
  ASSERT_TRUE(nodes.writer->wait_for_match(Topic::ultrasound_frame, 1, kMatchTimeoutNs));
  auto frame = make_frame(1024, 1024, 1);
  auto received = std::make_unique<UltrasoundFrame>();
  ASSERT_TRUE(wait_until([&] {
    ++frame->source_time_ns;
    nodes.writer->write(*frame);
    return ring->try_pop(*received);
  }));
  EXPECT_EQ(received->pixel_count(), kMaxFramePixels);
  EXPECT_EQ(std::memcmp(received->pixels.data(), frame->pixels.data(), kMaxFramePixels), 0);
  EXPECT_EQ(received->depth_m, frame->depth_m);
}

TEST(DdsPubSub, OutboxOutputsReachTheDisplayWithHealthCounters) {
  NodePair nodes = make_pair(103);
  auto outbox = std::make_unique<StationOutbox>();
  OutboxPublisher publisher;
  auto needle = std::make_unique<RingSink<NeedleState, 4>>();
  auto predictions = std::make_unique<RingSink<TargetPrediction, 4>>();
  auto surfaces = std::make_unique<RingSink<DeformedSurface, 2>>();
  auto health = std::make_unique<RingSink<StationHealth, 4>>();
  ASSERT_TRUE(nodes.writer->advertise<NeedleState>().ok());
  ASSERT_TRUE(nodes.writer->advertise<TargetPrediction>().ok());
  ASSERT_TRUE(nodes.writer->advertise<DeformedSurface>().ok());
  ASSERT_TRUE(nodes.writer->advertise<StationHealth>().ok());
  // Health is transient-local: published before the display subscribes, it still arrives.
  ASSERT_TRUE(outbox->health.try_push(make_health(5)));
  EXPECT_EQ(publisher.publish(*outbox, *nodes.writer, 0), 1u);
  ASSERT_TRUE(nodes.reader->subscribe(*needle).ok());
  ASSERT_TRUE(nodes.reader->subscribe(*predictions).ok());
  ASSERT_TRUE(nodes.reader->subscribe(*surfaces).ok());
  ASSERT_TRUE(nodes.reader->subscribe(*health).ok());
  for (const Topic topic :
       {Topic::needle_state, Topic::target_prediction, Topic::deformed_surface, Topic::station_health}) {
    ASSERT_TRUE(nodes.writer->wait_for_match(topic, 1, kMatchTimeoutNs)) << topic_name(topic);
  }
  StationHealth late_health;
  ASSERT_TRUE(wait_until([&] { return health->try_pop(late_health); }));
  EXPECT_EQ(late_health.step_time_max_ns, 420'000);
  EXPECT_EQ(late_health.input_age_ns, make_health(5).input_age_ns);  // "none yet" included

  ASSERT_TRUE(outbox->needle.try_push(make_needle(32, 10)));
  ASSERT_TRUE(outbox->predictions.try_push(make_prediction(10)));
  ASSERT_TRUE(outbox->surfaces.try_push(*make_surface(kMaxSurfaceVertices, 10)));
  EXPECT_EQ(publisher.publish(*outbox, *nodes.writer, 0), 3u);
  NeedleState needle_in;
  TargetPrediction prediction_in;
  auto surface_in = std::make_unique<DeformedSurface>();
  ASSERT_TRUE(wait_until([&] { return needle->try_pop(needle_in); }));
  ASSERT_TRUE(wait_until([&] { return predictions->try_pop(prediction_in); }));
  ASSERT_TRUE(wait_until([&] { return surfaces->try_pop(*surface_in); }));
  EXPECT_EQ(needle_in.point_count, 32u);
  EXPECT_EQ(needle_in.shape_points_m[31], make_needle(32, 10).shape_points_m[31]);
  EXPECT_EQ(prediction_in.position_m, make_prediction(10).position_m);
  EXPECT_EQ(surface_in->vertex_count, kMaxSurfaceVertices);
  EXPECT_EQ(surface_in->vertex_positions_m[kMaxSurfaceVertices - 1],
            make_surface(kMaxSurfaceVertices, 10)->vertex_positions_m[kMaxSurfaceVertices - 1]);
}

/// The bad samples of every kind, sent until each is counted; then the station's health
/// carries the counts to a display.
// The loop-rate forces leave the outbox on their own best-effort topic, counted apart from the
// other outputs; a burst beyond their ring is refused and counted there, never as an outbox
// overrun (the health's buffer_overrun stays down).
TEST(DdsPubSub, NeedleForcesReachTheDisplayBestEffortAndCountedApart) {
  NodePair nodes = make_pair(105);
  auto outbox = std::make_unique<StationOutbox>();
  OutboxPublisher publisher;
  auto forces = std::make_unique<RingSink<NeedleForce, 256>>();
  ASSERT_TRUE(nodes.writer->advertise<NeedleForce>().ok());
  ASSERT_TRUE(nodes.reader->subscribe(*forces).ok());
  ASSERT_TRUE(nodes.writer->wait_for_match(Topic::needle_force, 1, kMatchTimeoutNs));
  EXPECT_EQ(writer_qos(Topic::needle_force, {}).reliability().kind,
            eprosima::fastdds::dds::BEST_EFFORT_RELIABILITY_QOS);
  constexpr int kBurst = 80;  // more than the ring's 64
  int pushed = 0;
  for (int i = 0; i < kBurst; ++i) pushed += outbox->needle_forces.try_push(make_needle_force(1000 + i)) ? 1 : 0;
  EXPECT_EQ(pushed, 64);
  EXPECT_EQ(outbox->needle_forces.dropped(), static_cast<std::uint64_t>(kBurst - 64));
  EXPECT_EQ(outbox->dropped(), 0u);
  EXPECT_EQ(publisher.publish(*outbox, *nodes.writer, 0), 0u);  // no other output
  EXPECT_EQ(publisher.forces_written(), 64u);
  // Best effort: under load some of the burst may be lost; one force more a millisecond until
  // one arrives. What arrives comes in order, none twice.
  NeedleForce received;
  int count = 0;
  TimeNs last_ns = 0, next_ns = 1000 + kBurst;
  ASSERT_TRUE(wait_until([&] {
    while (forces->try_pop(received)) {
      ++count;
      EXPECT_GT(received.source_time_ns, last_ns);
      last_ns = received.source_time_ns;
    }
    if (count > 0) return true;
    outbox->needle_forces.try_push(make_needle_force(next_ns++));
    publisher.publish(*outbox, *nodes.writer, 0);
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
    return false;
  })) << count
      << " forces arrived";
  std::printf("%d of %llu forces written arrived\n", count,
              static_cast<unsigned long long>(publisher.forces_written()));
  EXPECT_EQ(received.tip_force_n, make_needle_force(0).tip_force_n);
  EXPECT_EQ(received.holder_force_n, make_needle_force(0).holder_force_n);
  EXPECT_EQ(received.tool_id, 12u);
}

TEST(DdsPubSub, BadSamplesAreDroppedCountedAndPublishedInHealth) {
  NodePair nodes = make_pair(104);
  DdsNode& tracker = *nodes.writer;
  DdsNode& station = *nodes.reader;
  PoseInbox inbox{1};
  auto frames = std::make_unique<RingSink<UltrasoundFrame, 2>>();
  ASSERT_TRUE(tracker.advertise<ToolPose>().ok());
  ASSERT_TRUE(tracker.advertise<UltrasoundFrame>().ok());
  ASSERT_TRUE(station.subscribe(inbox).ok());
  ASSERT_TRUE(station.subscribe(*frames).ok());
  ASSERT_TRUE(tracker.wait_for_match(Topic::tool_pose, 1, kMatchTimeoutNs));
  ASSERT_TRUE(tracker.wait_for_match(Topic::ultrasound_frame, 1, kMatchTimeoutNs));

  TimeNs time_ns = 1'000'000;
  ToolPose nan_pose = make_pose(1, 0);
  nan_pose.position_m[0] = std::numeric_limits<double>::quiet_NaN();
  ToolPose tilted = make_pose(1, 0);
  tilted.orientation_wxyz = {0.9, 0.1, 0.0, 0.0};
  auto frame = make_frame(64, 64, 0);
  frame->width_px = 2048;  // 2048 x 1024 announced, at most 1 MiB sent: sizes disagree
  frame->height_px = 1024;
  const auto sent_until_counted = [&](auto send, auto counted) {
    return wait_until([&] {
      send();
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
      return counted(station.boundary_counts()) >= 1;
    });
  };
  EXPECT_TRUE(sent_until_counted(
      [&] {
        nan_pose.source_time_ns = ++time_ns;
        tracker.write(nan_pose);
      },
      [](const BoundaryCounts& c) { return c.non_finite; }));
  EXPECT_TRUE(sent_until_counted(
      [&] {
        tilted.source_time_ns = ++time_ns;
        tracker.write(tilted);
      },
      [](const BoundaryCounts& c) { return c.non_unit_quaternion; }));
  EXPECT_TRUE(sent_until_counted([&] { tracker.write(make_pose(9, ++time_ns)); },
                                 [](const BoundaryCounts& c) { return c.unknown_tool; }));
  EXPECT_TRUE(sent_until_counted(
      [&] {
        time_ns += 10;
        tracker.write(make_pose(1, time_ns));
        tracker.write(make_pose(1, time_ns - 5));
      },
      [](const BoundaryCounts& c) { return c.time_backwards; }));
  EXPECT_TRUE(sent_until_counted(
      [&] {
        frame->source_time_ns = ++time_ns;
        tracker.write(*frame);
      },
      [](const BoundaryCounts& c) { return c.wrong_size; }));
  // Nothing bad got through: the inbox holds a good pose, the frame ring nothing.
  ASSERT_TRUE(inbox.update(0));
  EXPECT_TRUE(std::isfinite(inbox.latest(0).position_m[0]));
  EXPECT_EQ(inbox.latest(0).orientation_wxyz, make_pose(1, 0).orientation_wxyz);
  auto popped = std::make_unique<UltrasoundFrame>();
  EXPECT_FALSE(frames->try_pop(*popped));

  // The counts leave in the station's health, with bad_sample raised for as long as its hold
  // after the last refusal seen: on the station, and on each input that had one (tool 1 as the
  // needle, the frames as the ultrasound; the probe had none).
  auto display = DdsNode::create(local_network(104));
  ASSERT_TRUE(display.ok());
  auto health = std::make_unique<RingSink<StationHealth, 4>>();
  auto outbox = std::make_unique<StationOutbox>();
  OutboxPublisher publisher;
  ASSERT_TRUE(station.advertise<StationHealth>().ok());
  ASSERT_TRUE(display.value()->subscribe(*health).ok());
  ASSERT_TRUE(display.value()->wait_for_match(Topic::station_health, 1, kMatchTimeoutNs));
  ASSERT_TRUE(outbox->health.try_push(make_health(time_ns)));
  constexpr TimeNs kPublishedAtNs = 100 * kNsPerSecond;
  constexpr auto bad_sample = static_cast<std::uint32_t>(HealthFlag::bad_sample);
  const auto needle = static_cast<std::size_t>(StationInput::needle),
             probe = static_cast<std::size_t>(StationInput::probe),
             ultrasound = static_cast<std::size_t>(StationInput::ultrasound);
  const PerInput<std::uint64_t> refused{inbox.refused(0), 0, 0,
                                        refused_as_invalid(station.boundary_counts(Topic::ultrasound_frame))};
  publisher.publish(*outbox, station, kPublishedAtNs, refused);
  StationHealth received;
  ASSERT_TRUE(wait_until([&] { return health->try_pop(received); }));
  EXPECT_TRUE(received.flags & bad_sample);
  EXPECT_TRUE(received.input_flags[needle] & bad_sample);
  EXPECT_TRUE(received.input_flags[ultrasound] & bad_sample);
  EXPECT_EQ(received.input_flags[probe], 0u);
  EXPECT_EQ(received.input_refused, refused);
  EXPECT_EQ(received.pose_writers, 1u);  // the tracker's writers, as the station's readers matched them
  EXPECT_EQ(received.frame_writers, 1u);
  StationHealth later;
  for (const TimeNs after_ns : {kBadSampleHoldNs - 1, kBadSampleHoldNs}) {
    ASSERT_TRUE(outbox->health.try_push(make_health(time_ns)));
    publisher.publish(*outbox, station, kPublishedAtNs + after_ns, refused);
    ASSERT_TRUE(wait_until([&] { return health->try_pop(later); }));
    const bool held = after_ns < kBadSampleHoldNs;
    EXPECT_EQ((later.flags & bad_sample) != 0, held) << after_ns;
    EXPECT_EQ((later.input_flags[needle] & bad_sample) != 0, held) << after_ns;
    EXPECT_EQ((later.input_flags[ultrasound] & bad_sample) != 0, held) << after_ns;
  }
  // One more refusal of the needle alone raises its flag again, not the ultrasound's.
  PerInput<std::uint64_t> one_more = refused;
  ++one_more[needle];
  ASSERT_TRUE(outbox->health.try_push(make_health(time_ns)));
  publisher.publish(*outbox, station, kPublishedAtNs + 2 * kBadSampleHoldNs, one_more);
  ASSERT_TRUE(wait_until([&] { return health->try_pop(later); }));
  EXPECT_TRUE(later.input_flags[needle] & bad_sample);
  EXPECT_EQ(later.input_flags[ultrasound] & bad_sample, 0u);

  // Each refusal is also its input's: tool 1's poses refused at the boundary (NaN, tilted) and
  // by the inbox (backwards) count for its slot, tool 9's for none; the frame for the frames' reader.
  const BoundaryCounts counts = station.boundary_counts();
  EXPECT_EQ(inbox.refused(0), counts.non_finite + counts.non_unit_quaternion + counts.time_backwards);
  EXPECT_EQ(station.boundary_counts(Topic::tool_pose).unknown_tool, counts.unknown_tool);
  EXPECT_EQ(station.boundary_counts(Topic::tool_pose).wrong_size, 0u);
  EXPECT_EQ(station.boundary_counts(Topic::ultrasound_frame).wrong_size, counts.wrong_size);
  EXPECT_EQ(
      station.boundary_counts(Topic::ultrasound_frame).accepted + station.boundary_counts(Topic::tool_pose).accepted,
      counts.accepted);
  EXPECT_GE(received.boundary.non_finite, 1u);
  EXPECT_GE(received.boundary.non_unit_quaternion, 1u);
  EXPECT_GE(received.boundary.unknown_tool, 1u);
  EXPECT_GE(received.boundary.time_backwards, 1u);
  EXPECT_GE(received.boundary.wrong_size, 1u);
  EXPECT_LE(received.boundary.non_finite, counts.non_finite);
  EXPECT_GE(received.boundary.accepted, 1u);
}

}  // namespace
}  // namespace nav::dds
