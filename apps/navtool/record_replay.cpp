// navtool record / replay: writes every station topic seen on a DDS domain to an indexed
// recording, and plays a recording back onto a domain at the recorded pace or at once; with
// --scene, on the scene's domain and topic names.
#include <chrono>
#include <cstdio>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include "commands.hpp"
#include "nav/dds/record_replay.hpp"
#include "nav/dds/stop_request.hpp"
#include "nav/station/scene.hpp"
#include "nav/station/station_dds.hpp"

namespace navtool {
namespace {

/// The options shared by record and replay.
struct DdsToolArgs {
  std::string file;
  std::string scene_path;  ///< the scene whose domain, topic names and network to use (flags given after it win)
  nav::dds::NetworkConfig network;
  nav::dds::TopicQosOptions qos;
  double duration_s = 10.0;
  double wait_for_readers_s = 2.0;  // replay: how long each topic waits for its first reader
  bool as_fast_as_possible = false;
};

/// Takes the domain and topic names of the scene at `path`; false (after printing why) when it does not load.
bool take_scene(const std::string& path, DdsToolArgs& parsed) {
  auto scene = nav::station::scene_dds(path, nav::station::Role::tool);
  if (!scene.ok()) {
    std::fprintf(stderr, "navtool: %s\n", scene.error().describe().c_str());
    return false;
  }
  parsed.scene_path = path;
  parsed.network = scene.value().network;
  parsed.qos.names = scene.value().names;
  return true;
}

bool parse(const std::vector<std::string>& args, bool recording, DdsToolArgs& parsed) {
  for (std::size_t i = 1; i < args.size(); ++i) {
    const bool has_value = i + 1 < args.size();
    try {
      if (args[i] == "--domain" && has_value) {
        const long domain = std::stol(args[++i]);  // a DDS domain id: 0..232
        if (domain < 0 || domain > 232) return false;
        parsed.network.domain_id = static_cast<std::uint32_t>(domain);
      } else if (args[i] == "--scene" && has_value) {
        if (!take_scene(args[++i], parsed)) return false;
      } else if (args[i] == "--local-address" && has_value)
        parsed.network.local_address = args[++i];
      else if (args[i] == "--peer" && has_value)
        parsed.network.peer_addresses.push_back(args[++i]);
      else if (recording && args[i] == "--out" && has_value)
        parsed.file = args[++i];
      else if (recording && args[i] == "--duration-s" && has_value)
        parsed.duration_s = std::stod(args[++i]);
      else if (!recording && args[i] == "--as-fast-as-possible")
        parsed.as_fast_as_possible = true;
      else if (!recording && args[i] == "--wait-for-readers-s" && has_value)
        parsed.wait_for_readers_s = std::stod(args[++i]);
      else if (!recording && parsed.file.empty() && args[i].rfind("--", 0) != 0)
        parsed.file = args[i];
      else
        return false;
    } catch (const std::exception&) {
      return false;
    }
  }
  parsed.network.participant_name = recording ? "navtool_record" : "navtool_replay";
  return !parsed.file.empty() && parsed.duration_s > 0.0 && parsed.wait_for_readers_s >= 0.0;
}

int record(const DdsToolArgs& args) {
  std::unique_ptr<nav::dds::Recorder> recorder;  // declared first, destroyed after the node whose listeners fill it
  auto node = nav::dds::DdsNode::create(args.network, args.qos);
  if (!node) {
    std::fprintf(stderr, "navtool record: %s\n", node.error().describe().c_str());
    return exit_bad_input;
  }
  auto created = nav::dds::Recorder::create(*node.value(), args.file);
  if (!created) {
    std::fprintf(stderr, "navtool record: %s\n", created.error().describe().c_str());
    return exit_failure;
  }
  recorder = std::move(created).value();
  nav::dds::install_stop_handlers();  // SIGINT/SIGTERM end the recording with its index
  std::size_t records = 0;
  const auto until = std::chrono::steady_clock::now() + std::chrono::duration<double>(args.duration_s);
  for (bool last_pump = false; !last_pump;) {
    last_pump = nav::dds::stop_requested() || std::chrono::steady_clock::now() >= until;
    if (!last_pump) std::this_thread::sleep_for(std::chrono::milliseconds(2));
    const auto written = recorder->pump();
    if (!written) {
      std::fprintf(stderr, "navtool record: %s\n", written.error().describe().c_str());
      return exit_failure;
    }
    records += written.value();
  }
  if (const nav::Status closed = recorder->close(); !closed) {
    std::fprintf(stderr, "navtool record: %s\n", closed.error().describe().c_str());
    return exit_failure;
  }
  const nav::dds::BoundaryCounts counts = node.value()->boundary_counts();
  std::printf("recorded %zu samples to %s (dropped at the boundary: %s)\n", records, args.file.c_str(),
              nav::dds::drops_by_reason(counts).c_str());
  return exit_ok;
}

int replay(const DdsToolArgs& args) {
  auto recording = nav::dds::RecordingReader::open(args.file);
  if (!recording) {
    std::fprintf(stderr, "navtool replay: %s\n", recording.error().describe().c_str());
    return exit_bad_input;
  }
  if (recording.value()->damage()) {
    std::fprintf(stderr, "navtool replay: damaged recording: %s; playing the intact part\n",
                 recording.value()->damage()->describe().c_str());
  }
  auto node = nav::dds::DdsNode::create(args.network, args.qos);
  if (!node) {
    std::fprintf(stderr, "navtool replay: %s\n", node.error().describe().c_str());
    return exit_bad_input;
  }
  const auto pace =
      args.as_fast_as_possible ? nav::dds::ReplayPace::as_fast_as_possible : nav::dds::ReplayPace::recorded;
  const auto wait_for_readers_ns = static_cast<nav::TimeNs>(args.wait_for_readers_s * 1e9);
  const nav::dds::ReplayReport report = nav::dds::replay(*recording.value(), *node.value(), pace, wait_for_readers_ns);
  if (report.first_damage)
    std::fprintf(stderr, "navtool replay: skipped: %s\n", report.first_damage->describe().c_str());
  std::printf("replayed %zu samples, skipped %zu\n", report.published, report.skipped);
  if (!report.acknowledged) std::fprintf(stderr, "navtool replay: some reliable samples were not acknowledged\n");
  return recording.value()->damage() || report.skipped > 0 ? exit_failure : exit_ok;
}

}  // namespace

int record_replay(const std::vector<std::string>& args) {
  DdsToolArgs parsed;
  const bool recording = !args.empty() && args[0] == "record";
  if (args.empty() || !parse(args, recording, parsed)) {
    std::fputs(recording ? "usage: navtool record --out FILE [--duration-s S] [--scene FILE] [--domain D] "
                           "[--local-address A] [--peer A]...\n"
                         : "usage: navtool replay FILE [--as-fast-as-possible] [--wait-for-readers-s S] [--scene FILE] "
                           "[--domain D] [--local-address A] [--peer A]...\n",
               stderr);
    return exit_bad_input;
  }
  return recording ? record(parsed) : replay(parsed);
}

}  // namespace navtool
