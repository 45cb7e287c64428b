// The publishing side of navbench dds, shared by the in-process runs (in a thread) and the
// cross-process runs (the "navbench dds-peer" child process).
#include <chrono>
#include <cstdio>
#include <memory>
#include <thread>

#include "dds_bench.hpp"
#include "nav/station/security_roles.hpp"

namespace navbench {
namespace {

using nav::dds::DdsNode;

constexpr nav::TimeNs kMatchTimeoutNs = 10 * nav::kNsPerSecond;

/// A full-size (1024 x 1024) frame with a fixed pattern.
std::unique_ptr<nav::dds::UltrasoundFrame> make_bench_frame() {
  auto frame = std::make_unique<nav::dds::UltrasoundFrame>();
  frame->width_px = 1024;
  frame->height_px = 1024;
  frame->pixel_spacing_m = {1e-4, 1e-4};
  frame->depth_m = 0.1;
  for (std::size_t i = 0; i < frame->pixel_count(); ++i) frame->pixels[i] = static_cast<std::uint8_t>(i % 251);
  return frame;
}

/// Sends plan.samples of `sample` at the plan's pace, stamping each with its send time.
template <typename Sample>
void send_paced(DdsNode& node, const PublishPlan& plan, Sample& sample) {
  nav::MonotonicClock clock;
  nav::TimeNs next_ns = clock.now_ns();
  for (std::uint64_t i = 0; i < plan.samples; ++i) {
    if (plan.period_ns > 0) {
      next_ns += plan.period_ns;
      clock.sleep_until_ns(next_ns);
    }
    sample.sequence_number = i;
    sample.source_time_ns = clock.now_ns();
    node.write(sample);
  }
}

}  // namespace

bool publish_stream(DdsNode& node, const PublishPlan& plan) {
  const nav::dds::Topic topic =
      plan.stream == Stream::pose ? nav::dds::Topic::tool_pose : nav::dds::Topic::ultrasound_frame;
  const bool advertised = plan.stream == Stream::pose ? node.advertise<nav::dds::ToolPose>().ok()
                                                      : node.advertise<nav::dds::UltrasoundFrame>().ok();
  if (!advertised || !node.wait_for_match(topic, 1, kMatchTimeoutNs)) return false;
  std::this_thread::sleep_for(std::chrono::milliseconds(200));  // let the reader's side match too
  if (plan.stream == Stream::pose) {
    nav::dds::ToolPose pose;
    pose.tool_id = 1;
    send_paced(node, plan, pose);
  } else {
    auto frame = make_bench_frame();
    send_paced(node, plan, *frame);
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(200));  // let the last samples land
  return true;
}

nav::dds::NetworkConfig bench_network(const PublishPlan& plan, const char* participant_name, bool writer) {
  nav::dds::NetworkConfig network;
  network.domain_id = plan.domain_id;
  network.participant_name = participant_name;
  if (!plan.security_dir.empty())
    network.security = nav::station::security_files(nav::station::security_folder(plan.security_dir),
                                                    writer ? nav::station::Role::devices : nav::station::Role::station);
  return network;
}

std::vector<std::string> to_peer_arguments(const PublishPlan& plan) {
  return {plan.stream == Stream::pose ? "pose" : "frame",
          std::to_string(plan.domain_id),
          std::to_string(plan.samples),
          std::to_string(plan.period_ns),
          plan.data_sharing ? "1" : "0",
          plan.security_dir.empty() ? "-" : plan.security_dir};
}

bool from_peer_arguments(const std::vector<std::string>& args, PublishPlan& plan) {
  if (args.size() != 6 || (args[0] != "pose" && args[0] != "frame")) return false;
  plan.security_dir = args[5] == "-" ? "" : args[5];
  try {
    plan.stream = args[0] == "pose" ? Stream::pose : Stream::frame;
    plan.domain_id = static_cast<std::uint32_t>(std::stoul(args[1]));
    plan.samples = std::stoull(args[2]);
    plan.period_ns = std::stoll(args[3]);
    plan.data_sharing = args[4] == "1";
  } catch (const std::exception&) {
    return false;
  }
  return true;
}

int run_dds_peer(const std::vector<std::string>& args) {
  PublishPlan plan;
  if (!from_peer_arguments(args, plan)) {
    std::fputs("navbench dds-peer: malformed arguments (internal command of navbench dds)\n", stderr);
    return 2;
  }
  const nav::dds::NetworkConfig network = bench_network(plan, "navbench_peer", true);
  nav::dds::TopicQosOptions qos;
  qos.data_sharing = plan.data_sharing;
  auto node = DdsNode::create(network, qos);
  if (!node) {
    std::fprintf(stderr, "navbench dds-peer: %s\n", node.error().describe().c_str());
    return 1;
  }
  if (!publish_stream(*node.value(), plan)) {
    std::fputs("navbench dds-peer: no reader matched within 10 s\n", stderr);
    return 1;
  }
  return 0;
}

}  // namespace navbench
