// Tracker drivers end to end on DDS: the simulated tracker and the NDI driver (against the
// simulated device on a pseudo-terminal) publish ToolPose samples that a station node
// receives intact, with frame names, quality and time; missing tools are not published.
// Prints the sample-in to DDS-sample-out latency.
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <thread>

#include "nav/dds/dds_node.hpp"
#include "nav/trackers/ndi_simulator.hpp"
#include "nav/trackers/ndi_tracker.hpp"
#include "nav/trackers/pose_publisher.hpp"
#include "nav/trackers/simulated_tracker.hpp"

namespace nav::trackers {
namespace {

constexpr TimeNs kMatchTimeoutNs = 10 * kNsPerSecond;

dds::NetworkConfig loopback(std::uint32_t domain_id) {
  dds::NetworkConfig config;
  config.domain_id = domain_id;
  config.participant_name = "nav_tracker_test";
  return config;
}

/// A tracker node publishing and a station node receiving every pose.
struct Link {
  std::unique_ptr<dds::DdsNode> tracker;
  std::unique_ptr<dds::DdsNode> station;
  std::unique_ptr<dds::RingSink<dds::ToolPose, 256>> received = std::make_unique<dds::RingSink<dds::ToolPose, 256>>();
};

Link open_link(std::uint32_t domain_id) {
  Link link;
  auto tracker = dds::DdsNode::create(loopback(domain_id));
  auto station = dds::DdsNode::create(loopback(domain_id));
  EXPECT_TRUE(tracker.ok() && station.ok());
  link.tracker = std::move(tracker).value();
  link.station = std::move(station).value();
  EXPECT_TRUE(link.station->subscribe<dds::ToolPose>(*link.received).ok());
  return link;
}

/// Pops poses until `count` arrived or 5 s passed.
std::vector<dds::ToolPose> receive(Link& link, std::size_t count) {
  std::vector<dds::ToolPose> poses;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(5);
  dds::ToolPose pose;
  while (poses.size() < count && std::chrono::steady_clock::now() < deadline) {
    if (link.received->try_pop(pose)) {
      poses.push_back(pose);
    } else {
      std::this_thread::sleep_for(std::chrono::microseconds(200));
    }
  }
  return poses;
}

void print_latency(const char* driver, std::vector<TimeNs> latencies_ns) {
  std::sort(latencies_ns.begin(), latencies_ns.end());
  std::printf("%s: sample in -> DDS sample out: median %.1f us, max %.1f us (%zu samples)\n", driver,
              static_cast<double>(latencies_ns[latencies_ns.size() / 2]) * 1e-3,
              static_cast<double>(latencies_ns.back()) * 1e-3, latencies_ns.size());
}

TEST(TrackerDds, SimulatedTrackerPosesArriveIntact) {
  Link link = open_link(171);
  auto publisher = PosePublisher::create(*link.tracker, "tracker", {{1, "needle_marker"}, {2, "probe_marker"}});
  ASSERT_TRUE(publisher.ok()) << publisher.error().describe();
  // Both sides matched: the station's reader knows the writer before the first sample.
  ASSERT_TRUE(link.tracker->wait_for_match(dds::Topic::tool_pose, 1, kMatchTimeoutNs));
  ASSERT_TRUE(link.station->wait_for_match(dds::Topic::tool_pose, 1, kMatchTimeoutNs));
  SimulatedTrackerConfig config;
  config.tools = {{1, Trajectory{}, 0.25}, {2, Trajectory{}, 0.0}};
  config.period_ns = kNsPerMs;
  config.seed = 5;
  SimulatedTracker tracker(config);
  std::vector<TrackerSample> samples;
  tracker.poll(39 * kNsPerMs, samples);  // 40 frames x 2 tools
  const MonotonicClock clock;
  std::vector<TimeNs> sent_ns;
  for (const TrackerSample& sample : samples) {
    const TimeNs before_ns = clock.now_ns();
    if (publisher.value().publish(sample)) sent_ns.push_back(before_ns);
  }
  const PublishCounts counts = publisher.value().counts();
  EXPECT_EQ(counts.published + counts.without_pose, 80u);
  EXPECT_GT(counts.without_pose, 0u);
  const std::vector<dds::ToolPose> poses = receive(link, counts.published);
  ASSERT_EQ(poses.size(), counts.published);
  std::vector<TimeNs> latencies_ns;
  std::size_t published_index = 0;
  for (const TrackerSample& sample : samples) {
    if (!has_pose(sample.state)) continue;
    const dds::ToolPose& pose = poses[published_index];
    EXPECT_EQ(pose.tool_id, sample.tool_id);
    EXPECT_EQ(pose.source_time_ns, sample.measured_time_ns);
    EXPECT_EQ(pose.position_m, sample.position_m);
    EXPECT_STREQ(pose.frame_to.data(), "tracker");
    EXPECT_STREQ(pose.frame_from.data(), sample.tool_id == 1 ? "needle_marker" : "probe_marker");
    EXPECT_EQ(pose.quality, 1.0f);
    latencies_ns.push_back(pose.receive_time_ns - sent_ns[published_index]);
    ++published_index;
  }
  print_latency("simulated tracker (publish -> receive)", latencies_ns);
}

TEST(TrackerDds, NdiDriverPublishesBxPosesWithToolStates) {
  Link link = open_link(172);
  auto publisher = PosePublisher::create(*link.tracker, "tracker", {{1, "needle_marker"}});
  ASSERT_TRUE(publisher.ok());
  // Both sides matched: the station's reader knows the writer before the first sample.
  ASSERT_TRUE(link.tracker->wait_for_match(dds::Topic::tool_pose, 1, kMatchTimeoutNs));
  ASSERT_TRUE(link.station->wait_for_match(dds::Topic::tool_pose, 1, kMatchTimeoutNs));
  auto pty = ndi::open_pseudo_terminal();
  ASSERT_TRUE(pty.ok());
  auto connection = ndi::Connection::open_serial(pty.value().slave_path);
  ASSERT_TRUE(connection.ok());
  ndi::SimulatedNdiTool needle;
  needle.handle = 1;
  needle.missing_every = 4;
  needle.partly_out_every = 3;
  ndi::NdiDeviceServer server(pty.value().master_fd, ndi::SimulatedNdiDevice({needle}));
  auto tracker = ndi::NdiTracker::start(std::move(connection).value());
  ASSERT_TRUE(tracker.ok()) << tracker.error().describe();
  const MonotonicClock clock;
  std::vector<TimeNs> requested_ns;
  for (int frame = 0; frame < 24; ++frame) {
    const TimeNs request_ns = clock.now_ns();
    auto samples = tracker.value().poll(ndi::ReplyFormat::bx, request_ns);
    ASSERT_TRUE(samples.ok()) << samples.error().describe();
    if (publisher.value().publish(samples.value().front())) requested_ns.push_back(request_ns);
  }
  EXPECT_EQ(publisher.value().counts().without_pose, 6u);  // frames 0, 4, ..., 20
  const std::vector<dds::ToolPose> poses = receive(link, 18);
  const dds::BoundaryCounts boundary = link.station->boundary_counts();
  ASSERT_EQ(poses.size(), 18u) << "accepted " << boundary.accepted << ", non-finite " << boundary.non_finite
                               << ", non-unit " << boundary.non_unit_quaternion << ", backwards "
                               << boundary.time_backwards;
  std::vector<TimeNs> latencies_ns;
  std::size_t partly = 0;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    partly += poses[i].quality == 0.5f;
    EXPECT_EQ(poses[i].source_time_ns, requested_ns[i]);
    latencies_ns.push_back(poses[i].receive_time_ns - requested_ns[i]);
  }
  EXPECT_EQ(partly, 6u);  // frames 3, 6, 9, 15, 18, 21 (0 and 12 are missing)
  print_latency("NDI BX over a pty (request -> receive)", latencies_ns);
}

}  // namespace
}  // namespace nav::trackers
