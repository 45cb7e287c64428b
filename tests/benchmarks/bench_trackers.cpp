// Tracker driver latency, sample in -> DDS sample out, with medians and tails as counters:
//  - NDI: BX (binary) and TX (text) request over a pseudo-terminal to the simulated device,
//    reply decoded, pose published and received by a station node on DDS (loopback/SHM);
//  - AprilTag: one 640x480 frame detected and its body pose published and received;
//  - simulated tracker: a sample published and received.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <optional>
#include <thread>

#include "nav/dds/dds_node.hpp"
#include "nav/trackers/apriltag_tracker.hpp"
#include "nav/trackers/ndi_simulator.hpp"
#include "nav/trackers/ndi_tracker.hpp"
#include "nav/trackers/pose_publisher.hpp"
#include "nav/trackers/simulated_tracker.hpp"

namespace {

using namespace nav;
using namespace nav::trackers;

/// A publisher node and a station node on one domain, with the pose topic matched both ways.
struct DdsLink {
  std::unique_ptr<dds::DdsNode> tracker;
  std::unique_ptr<dds::DdsNode> station;
  std::unique_ptr<dds::RingSink<dds::ToolPose, 64>> sink = std::make_unique<dds::RingSink<dds::ToolPose, 64>>();
  std::optional<PosePublisher> publisher;

  explicit DdsLink(std::uint32_t domain_id) {
    dds::NetworkConfig network;
    network.domain_id = domain_id;
    tracker = std::move(dds::DdsNode::create(network)).value();
    station = std::move(dds::DdsNode::create(network)).value();
    (void)station->subscribe<dds::ToolPose>(*sink);
    publisher.emplace(std::move(PosePublisher::create(*tracker, "tracker", {})).value());
    tracker->wait_for_match(dds::Topic::tool_pose, 1, 10 * kNsPerSecond);
    station->wait_for_match(dds::Topic::tool_pose, 1, 10 * kNsPerSecond);
  }
  /// Publishes and spins until the station has the sample; the receive time.
  TimeNs round_trip(const TrackerSample& sample) {
    publisher->publish(sample);
    dds::ToolPose pose;
    while (!sink->try_pop(pose)) std::this_thread::yield();
    return pose.receive_time_ns;
  }
};

void report(benchmark::State& state, std::vector<TimeNs>& latencies_ns) {
  std::sort(latencies_ns.begin(), latencies_ns.end());
  const auto at = [&](double q) { return static_cast<double>(latencies_ns[static_cast<std::size_t>(q * (latencies_ns.size() - 1))]) * 1e-3; };
  state.counters["p50_us"] = at(0.5);
  state.counters["p99_us"] = at(0.99);
  state.counters["max_us"] = at(1.0);
}

void ndi_latency(benchmark::State& state, ndi::ReplyFormat format, std::uint32_t domain_id) {
  DdsLink link(domain_id);
  auto pty = std::move(ndi::open_pseudo_terminal()).value();
  auto connection = std::move(ndi::Connection::open_serial(pty.slave_path)).value();
  ndi::NdiDeviceServer server(pty.master_fd, ndi::SimulatedNdiDevice({ndi::SimulatedNdiTool{}}));
  auto tracker = std::move(ndi::NdiTracker::start(std::move(connection))).value();
  const MonotonicClock clock;
  std::vector<TimeNs> latencies_ns;
  for (auto _ : state) {
    const TimeNs request_ns = clock.now_ns();
    auto samples = tracker.poll(format, request_ns);
    latencies_ns.push_back(link.round_trip(samples.value().front()) - request_ns);
  }
  report(state, latencies_ns);
}

void BM_NdiBxToDds(benchmark::State& state) { ndi_latency(state, ndi::ReplyFormat::bx, 181); }
void BM_NdiTxToDds(benchmark::State& state) { ndi_latency(state, ndi::ReplyFormat::tx, 182); }

void BM_AprilTagFrameToDds(benchmark::State& state) {
  DdsLink link(183);
  const CameraIntrinsics camera;
  auto tracker = std::move(AprilTagTracker::create(camera, 0.05, {TagBody{1, {{7, Eigen::Isometry3d::Identity()}}}})).value();
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, -1, 0.2).normalized()).toRotationMatrix();
  pose.translation() = Eigen::Vector3d(0.01, -0.02, 0.3);
  const GrayImage frame = render_tags({{7, pose}}, 0.05, camera, 640, 480, 2.0, 1);
  const MonotonicClock clock;
  std::vector<TimeNs> latencies_ns;
  for (auto _ : state) {
    const TimeNs frame_in_ns = clock.now_ns();
    const std::vector<TrackerSample> samples = tracker->track(frame, frame_in_ns);
    latencies_ns.push_back(link.round_trip(samples.front()) - frame_in_ns);
  }
  report(state, latencies_ns);
}

void BM_SimulatedTrackerToDds(benchmark::State& state) {
  DdsLink link(184);
  SimulatedTrackerConfig config;
  config.tools = {{1, Trajectory{}, 0.0}};
  config.period_ns = 1;
  SimulatedTracker tracker(config);
  const MonotonicClock clock;
  std::vector<TimeNs> latencies_ns;
  std::vector<TrackerSample> samples;
  TimeNs device_time_ns = 0;
  for (auto _ : state) {
    samples.clear();
    tracker.poll(device_time_ns++, samples);
    const TimeNs sample_in_ns = clock.now_ns();
    latencies_ns.push_back(link.round_trip(samples.front()) - sample_in_ns);
  }
  report(state, latencies_ns);
}

BENCHMARK(BM_NdiBxToDds)->Iterations(2000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_NdiTxToDds)->Iterations(2000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_AprilTagFrameToDds)->Iterations(100)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SimulatedTrackerToDds)->Iterations(5000)->Unit(benchmark::kMicrosecond);

}  // namespace
