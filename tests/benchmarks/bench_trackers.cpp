// Device driver latency, sample in -> DDS sample out, with medians and tails as counters:
//  - NDI: BX (binary) and TX (text) request over a pseudo-terminal to the simulated device,
//    reply decoded, pose published and received by a station node on DDS (loopback/SHM);
//  - AprilTag: one 640x480 frame detected and its body pose published and received;
//  - simulated tracker: a sample published and received;
//  - ultrasound sources, frame in -> UltrasoundFrame received by a station node: the
//    synthetic B-mode device (256x256 render included), the PLUS sequence player (an
//    820x616 frame, the real recordings' size) and the OpenCV capture source (a 256x256 PNG
//    decoded from an image sequence).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <opencv2/core.hpp>
#include <opencv2/imgcodecs.hpp>
#include <optional>
#include <thread>

#include "nav/dds/dds_node.hpp"
#include "nav/trackers/apriltag_tracker.hpp"
#include "nav/trackers/ndi_simulator.hpp"
#include "nav/trackers/ndi_tracker.hpp"
#include "nav/trackers/pose_publisher.hpp"
#include "nav/trackers/simulated_tracker.hpp"
#include "nav/ultrasound/bmode_device.hpp"
#include "nav/ultrasound/capture_source.hpp"
#include "nav/ultrasound/sequence_player.hpp"

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
  const auto at = [&](double q) {
    return static_cast<double>(latencies_ns[static_cast<std::size_t>(q * (latencies_ns.size() - 1))]) * 1e-3;
  };
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
  auto tracker =
      std::move(AprilTagTracker::create(camera, 0.05, {TagBody{1, {{7, Eigen::Isometry3d::Identity()}}}})).value();
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

/// An ultrasound device node and a station node with the frame and pose topics matched.
struct FrameLink {
  std::unique_ptr<dds::DdsNode> device;
  std::unique_ptr<dds::DdsNode> station;
  std::unique_ptr<dds::RingSink<dds::UltrasoundFrame, 4>> frames =
      std::make_unique<dds::RingSink<dds::UltrasoundFrame, 4>>();
  std::unique_ptr<dds::RingSink<dds::ToolPose, 64>> poses = std::make_unique<dds::RingSink<dds::ToolPose, 64>>();
  std::unique_ptr<dds::UltrasoundFrame> received = std::make_unique<dds::UltrasoundFrame>();

  explicit FrameLink(std::uint32_t domain_id) {
    dds::NetworkConfig network;
    network.domain_id = domain_id;
    device = std::move(dds::DdsNode::create(network)).value();
    station = std::move(dds::DdsNode::create(network)).value();
    (void)station->subscribe<dds::UltrasoundFrame>(*frames);
    (void)station->subscribe<dds::ToolPose>(*poses);
    (void)device->advertise<dds::UltrasoundFrame>();
    (void)device->advertise<dds::ToolPose>();
    for (const dds::Topic topic : {dds::Topic::ultrasound_frame, dds::Topic::tool_pose}) {
      device->wait_for_match(topic, 1, 10 * kNsPerSecond);
      station->wait_for_match(topic, 1, 10 * kNsPerSecond);
    }
  }
  /// Spins until the station has the next frame; its receive time (poses are dropped).
  TimeNs next_frame_time_ns() {
    while (!frames->try_pop(*received)) std::this_thread::yield();
    dds::ToolPose pose;
    while (poses->try_pop(pose)) {
    }
    return received->receive_time_ns;
  }
};

void BM_BmodeDeviceFrameToDds(benchmark::State& state) {
  FrameLink link(185);
  const ultrasound::BmodeGeometry geometry;
  const ultrasound::BmodeScene scene = ultrasound::default_bmode_scene();
  ultrasound::BmodeDevice device(ultrasound::BmodeSimulator(geometry, scene, 3), Eigen::Isometry3d::Identity(), 2);
  const Eigen::Isometry3d probe = ultrasound::plane_through_tumour(geometry, scene, 0.0, 0.04);
  const MonotonicClock clock;
  std::vector<TimeNs> latencies_ns;
  bool published = false;
  for (auto _ : state) {
    const TimeNs frame_in_ns = clock.now_ns();
    device.publish(*link.device, probe, frame_in_ns, published);
    latencies_ns.push_back(link.next_frame_time_ns() - frame_in_ns);
  }
  report(state, latencies_ns);
}

void BM_SequencePlayerFrameToDds(benchmark::State& state) {
  FrameLink link(186);
  ultrasound::PlusSequence sequence;
  sequence.width_px = 820;
  sequence.height_px = 616;
  sequence.frame_count = sequence.frames_read = 1;
  sequence.timestamps_s = {0.0};
  sequence.image_valid = {1};
  sequence.pixels.resize(sequence.frame_pixels());
  for (std::size_t i = 0; i < sequence.pixels.size(); ++i) sequence.pixels[i] = static_cast<std::uint8_t>(i * 7);
  ultrasound::PlayOptions options;
  options.tools = {};
  options.as_fast_as_possible = true;
  MonotonicClock clock;
  std::vector<TimeNs> latencies_ns;
  for (auto _ : state) {
    const TimeNs frame_in_ns = clock.now_ns();
    (void)ultrasound::play_sequence(*link.device, sequence, options, clock);
    latencies_ns.push_back(link.next_frame_time_ns() - frame_in_ns);
  }
  report(state, latencies_ns);
}

void BM_CaptureSourceFrameToDds(benchmark::State& state) {
  FrameLink link(187);
  constexpr int kClipFrames = 20;
  const std::filesystem::path folder = std::filesystem::temp_directory_path() / "nav_bench_capture";
  std::filesystem::create_directories(folder);
  ultrasound::BmodeSimulator simulator(ultrasound::BmodeGeometry{}, ultrasound::default_bmode_scene(), 5);
  for (int i = 0; i < kClipFrames; ++i) {
    cv::Mat frame(256, 256, CV_8UC1);
    simulator.render(
        ultrasound::plane_through_tumour(simulator.geometry(), ultrasound::default_bmode_scene(), 1e-3 * i, 0.04),
        frame.data);
    char name[32];
    std::snprintf(name, sizeof name, "frame_%03d.png", i);
    cv::imwrite((folder / name).string(), frame);
  }
  const std::string pattern = (folder / "frame_%03d.png").string();
  MonotonicClock clock;
  std::unique_ptr<ultrasound::CaptureSource> capture;
  std::vector<TimeNs> latencies_ns;
  for (auto _ : state) {
    if (capture == nullptr || capture->frames_read() == kClipFrames) {
      state.PauseTiming();
      capture = std::move(ultrasound::CaptureSource::open(pattern, {}, clock)).value();
      state.ResumeTiming();
    }
    const TimeNs frame_in_ns = clock.now_ns();
    (void)capture->publish_next(*link.device);
    latencies_ns.push_back(link.next_frame_time_ns() - frame_in_ns);
  }
  report(state, latencies_ns);
  std::filesystem::remove_all(folder);
}

BENCHMARK(BM_NdiBxToDds)->Iterations(2000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_NdiTxToDds)->Iterations(2000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_AprilTagFrameToDds)->Iterations(100)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SimulatedTrackerToDds)->Iterations(5000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_BmodeDeviceFrameToDds)->Iterations(300)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_SequencePlayerFrameToDds)->Iterations(1000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_CaptureSourceFrameToDds)->Iterations(1000)->Unit(benchmark::kMicrosecond);

}  // namespace
