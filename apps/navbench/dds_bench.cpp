// navbench dds: runs each measurement with a fresh pair of DDS participants, the reader in
// this process and the writer either in a thread of it or in a child process, and writes
// the latency table as JSON.
#include "dds_bench.hpp"

#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cstdio>
#include <thread>
#include <tuple>

#include "latency_stats.hpp"

namespace navbench {
namespace {

using nav::TimeNs;
using nav::dds::SampleFault;

/// Records each received sample's one-way latency (receive minus send time, one monotonic
/// clock for the whole host) into preallocated storage. One producer: the DDS listener.
template <typename Sample>
class LatencySink final : public nav::dds::SampleSink<Sample> {
 public:
  explicit LatencySink(std::size_t capacity) : latencies_ns_(capacity) {}

  SampleFault offer(const Sample& sample) noexcept override {
    const std::size_t count = count_.load(std::memory_order_relaxed);
    if (count == latencies_ns_.size()) return SampleFault::buffer_full;
    latencies_ns_[count] = sample.receive_time_ns - sample.source_time_ns;
    if (count == 0) first_receive_ns_ = sample.receive_time_ns;
    last_receive_ns_ = sample.receive_time_ns;
    count_.store(count + 1, std::memory_order_release);
    return SampleFault::none;
  }

  /// After the run: the latencies received, and the span between first and last arrival.
  std::vector<TimeNs> latencies_ns() const {
    return {latencies_ns_.begin(),
            latencies_ns_.begin() + static_cast<std::ptrdiff_t>(count_.load(std::memory_order_acquire))};
  }
  TimeNs arrival_span_ns() const { return last_receive_ns_ - first_receive_ns_; }

 private:
  std::vector<TimeNs> latencies_ns_;
  std::atomic<std::size_t> count_{0};
  TimeNs first_receive_ns_ = 0;
  TimeNs last_receive_ns_ = 0;
};

/// One measurement: its name, the publisher's plan, and where the publisher runs.
struct Measurement {
  std::string name;
  PublishPlan plan;
  bool cross_process = false;
};

/// Runs the publisher as "navbench dds-peer" in a child process and waits for it.
bool run_peer_process(const PublishPlan& plan) {
  std::vector<std::string> args = {"navbench", "dds-peer"};
  for (std::string& arg : to_peer_arguments(plan)) args.push_back(std::move(arg));
  std::vector<char*> argv;
  for (std::string& arg : args) argv.push_back(arg.data());
  argv.push_back(nullptr);
  const pid_t child = fork();
  if (child < 0) return false;
  if (child == 0) {
    execv("/proc/self/exe", argv.data());
    _exit(127);
  }
  int status = 0;
  waitpid(child, &status, 0);
  return WIFEXITED(status) && WEXITSTATUS(status) == 0;
}

/// Subscribes a LatencySink of Sample, runs the publisher and summarizes what arrived.
template <typename Sample>
LatencyReport measure(const Measurement& measurement) {
  LatencyReport report;
  report.name = measurement.name;
  report.sent = measurement.plan.samples;
  const nav::dds::NetworkConfig network = bench_network(measurement.plan, "navbench", false);
  nav::dds::TopicQosOptions qos;
  qos.data_sharing = measurement.plan.data_sharing;
  auto reader = nav::dds::DdsNode::create(network, qos);
  LatencySink<Sample> sink(measurement.plan.samples);
  if (!reader || !reader.value()->subscribe(sink)) {
    std::fprintf(stderr, "navbench dds: %s: cannot create the reader\n", measurement.name.c_str());
    return report;
  }
  bool published = false;
  if (measurement.cross_process) {
    published = run_peer_process(measurement.plan);
  } else {
    auto writer = nav::dds::DdsNode::create(bench_network(measurement.plan, "navbench_writer", true), qos);
    published = writer && publish_stream(*writer.value(), measurement.plan);
  }
  if (!published) std::fprintf(stderr, "navbench dds: %s: the publisher failed\n", measurement.name.c_str());
  std::vector<TimeNs> latencies_ns = sink.latencies_ns();
  summarize_latencies(latencies_ns, report);
  if constexpr (std::is_same_v<Sample, nav::dds::UltrasoundFrame>) {
    if (measurement.plan.period_ns == 0 && report.received > 1 && sink.arrival_span_ns() > 0) {
      const double bytes = static_cast<double>(report.received - 1) * static_cast<double>(nav::dds::kMaxFramePixels);
      report.throughput_mb_per_s = bytes / (static_cast<double>(sink.arrival_span_ns()) / 1e9) / 1e6;
    }
  }
  return report;
}

/// The command line of navbench dds.
struct BenchArgs {
  std::string json_file;
  std::uint32_t domain_id = 140;
  std::uint64_t pose_samples = 5000;
  std::uint64_t frame_samples = 300;
  std::string security_dir;  // with it, the secured paths beside the unsecured ones
};

bool parse_args(const std::vector<std::string>& args, BenchArgs& parsed) {
  for (std::size_t i = 0; i + 1 < args.size(); i += 2) {
    const std::string& value = args[i + 1];
    try {
      if (args[i] == "--json")
        parsed.json_file = value;
      else if (args[i] == "--domain")
        parsed.domain_id = static_cast<std::uint32_t>(std::stoul(value));
      else if (args[i] == "--pose-samples")
        parsed.pose_samples = std::stoull(value);
      else if (args[i] == "--frame-samples")
        parsed.frame_samples = std::stoull(value);
      else if (args[i] == "--security")
        parsed.security_dir = value;
      else
        return false;
    } catch (const std::exception&) {
      return false;
    }
  }
  return args.size() % 2 == 0 && parsed.pose_samples > 0 && parsed.frame_samples > 0;
}

/// The measurements: poses at 2 kHz, frames at 100 Hz (latency) and unpaced (throughput);
/// with a security folder, the secured pose and frame paths next to unsecured ones without
/// data sharing (a secured participant sends through the transports too), twice, interleaved.
std::vector<Measurement> measurements(const BenchArgs& args) {
  const auto plan = [&](Stream stream, bool data_sharing, TimeNs period_ns, const std::string& security_dir = "") {
    return PublishPlan{stream,    args.domain_id, stream == Stream::pose ? args.pose_samples : args.frame_samples,
                       period_ns, data_sharing,   security_dir};
  };
  constexpr TimeNs kPosePeriodNs = 500'000;
  constexpr TimeNs kFramePeriodNs = 10 * nav::kNsPerMs;
  std::vector<Measurement> list{
      {"pose_in_process", plan(Stream::pose, true, kPosePeriodNs), false},
      {"pose_cross_process", plan(Stream::pose, true, kPosePeriodNs), true},
      {"pose_cross_process_no_data_sharing", plan(Stream::pose, false, kPosePeriodNs), true},
      {"frame_1mib_in_process", plan(Stream::frame, true, kFramePeriodNs), false},
      {"frame_1mib_cross_process", plan(Stream::frame, true, kFramePeriodNs), true},
      {"frame_1mib_cross_process_no_data_sharing", plan(Stream::frame, false, kFramePeriodNs), true},
      {"frame_1mib_throughput_cross_process", plan(Stream::frame, true, 0), true},
      {"frame_1mib_throughput_cross_process_no_data_sharing", plan(Stream::frame, false, 0), true},
  };
  if (args.security_dir.empty()) return list;
  for (const char* round : {"", "_again"}) {
    for (const auto& [stream, period_ns, name] :
         {std::tuple{Stream::pose, kPosePeriodNs, "pose"}, {Stream::frame, kFramePeriodNs, "frame_1mib"}}) {
      list.push_back({std::string(name) + "_cross_process_unsecured" + round, plan(stream, false, period_ns), true});
      list.push_back({std::string(name) + "_cross_process_secured" + round,
                      plan(stream, false, period_ns, args.security_dir), true});
    }
  }
  return list;
}

/// The report named `name`, or null.
const LatencyReport* report_named(const std::vector<LatencyReport>& reports, const std::string& name) {
  for (const LatencyReport& report : reports)
    if (report.name == name) return &report;
  return nullptr;
}

/// "secured / unsecured" latency ratios of each stream and round, as a JSON object (and printed).
Json security_cost_json(const std::vector<LatencyReport>& reports) {
  Json json = Json::object();
  for (const char* name : {"pose", "frame_1mib"}) {
    for (const char* round : {"", "_again"}) {
      const LatencyReport* plain = report_named(reports, std::string(name) + "_cross_process_unsecured" + round);
      const LatencyReport* secured = report_named(reports, std::string(name) + "_cross_process_secured" + round);
      if (plain == nullptr || secured == nullptr || plain->received == 0 || secured->received == 0) continue;
      const double p50 = secured->median_us / plain->median_us, p99 = secured->p99_us / plain->p99_us;
      std::printf("security cost, %s%s: median %.1f / %.1f us = %.2fx, p99 %.1f / %.1f us = %.2fx\n", name, round,
                  secured->median_us, plain->median_us, p50, secured->p99_us, plain->p99_us, p99);
      json[std::string(name) + round] = {{"median_ratio", p50}, {"p99_ratio", p99}};
    }
  }
  return json;
}

/// The p99 of the named report, or -1 when it is missing or received nothing.
double p99_of(const std::vector<LatencyReport>& reports, const std::string& name) {
  for (const LatencyReport& report : reports) {
    if (report.name == name && report.received > 0) return report.p99_us;
  }
  return -1.0;
}

}  // namespace

int run_dds_bench(const std::vector<std::string>& args) {
  BenchArgs parsed;
  if (!parse_args(args, parsed) || parsed.json_file.empty()) {
    std::fputs("usage: navbench dds --json FILE [--domain D] [--pose-samples N] [--frame-samples N] [--security DIR]\n",
               stderr);
    return 2;
  }
  std::vector<LatencyReport> reports;
  for (const Measurement& measurement : measurements(parsed)) {
    reports.push_back(measurement.plan.stream == Stream::pose ? measure<nav::dds::ToolPose>(measurement)
                                                              : measure<nav::dds::UltrasoundFrame>(measurement));
    std::printf("%s\n", to_text(reports.back()).c_str());
    std::fflush(stdout);
  }
  constexpr double kPoseTargetP99Us = 200.0;
  constexpr double kFrameTargetP99Us = 2000.0;
  const double pose_p99 = p99_of(reports, "pose_cross_process");
  const double frame_p99 = p99_of(reports, "frame_1mib_cross_process");
  const bool pose_met = pose_p99 >= 0.0 && pose_p99 <= kPoseTargetP99Us;
  const bool frame_met = frame_p99 >= 0.0 && frame_p99 <= kFrameTargetP99Us;
  std::printf("targets: pose across processes p99 %.1f us (<= %.0f: %s), 1 MiB frame p99 %.1f us (<= %.0f: %s)\n",
              pose_p99, kPoseTargetP99Us, pose_met ? "met" : "NOT met", frame_p99, kFrameTargetP99Us,
              frame_met ? "met" : "NOT met");

  Json results = Json::array();
  for (const LatencyReport& report : reports) results.push_back(to_json(report));
  Json document = {
      {"benchmark", "dds"},
      {"hardware_threads", std::thread::hardware_concurrency()},
      {"results", results},
      {"targets",
       {{"pose_cross_process_p99_us", kPoseTargetP99Us}, {"frame_1mib_cross_process_p99_us", kFrameTargetP99Us}}},
      {"targets_met", {{"pose_cross_process", pose_met}, {"frame_1mib_cross_process", frame_met}}}};
  if (!parsed.security_dir.empty()) document["security_cost"] = security_cost_json(reports);
  if (!write_json_document(parsed.json_file, document)) return 1;
  return 0;
}

}  // namespace navbench
