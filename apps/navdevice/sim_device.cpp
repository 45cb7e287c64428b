#include "sim_device.hpp"

#include <cstdio>
#include <memory>
#include <optional>

#include "nav/core/clock.hpp"
#include "nav/dds/sample_sink.hpp"
#include "nav/dds/stop_request.hpp"
#include "nav/station/scene.hpp"
#include "nav/station/simulated_world.hpp"
#include "nav/station/station_dds.hpp"
#include "nav/station/station_liver.hpp"
#include "nav/station/world_player.hpp"

namespace navdevice {
namespace {

using nav::TimeNs;
using nav::kNsPerMs;
using nav::kNsPerSecond;

constexpr int kExitError = 1;
constexpr int kExitUsage = 2;
constexpr TimeNs kPlayPeriodNs = kNsPerMs / 2;
constexpr TimeNs kStartDelayNs = 20 * kNsPerMs;  // from the station's match to world time 0

/// The command line of navdevice sim.
struct SimArgs {
  std::string scene_path;
  double seconds = 60.0;
  long domain_id = -1;  ///< -1: the scene's
  bool wait_for_station = true;
  double wait_s = 60.0;
};

std::optional<SimArgs> parse(const std::vector<std::string>& args) {
  SimArgs parsed;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const bool has_value = i + 1 < args.size();
    try {
      if (args[i] == "--scene" && has_value) parsed.scene_path = args[++i];
      else if (args[i] == "--seconds" && has_value) parsed.seconds = std::stod(args[++i]);
      else if (args[i] == "--domain" && has_value) parsed.domain_id = std::stol(args[++i]);
      else if (args[i] == "--wait-s" && has_value) parsed.wait_s = std::stod(args[++i]);
      else if (args[i] == "--no-wait") parsed.wait_for_station = false;
      else return std::nullopt;
    } catch (const std::exception&) {
      return std::nullopt;
    }
  }
  const bool valid = !parsed.scene_path.empty() && parsed.seconds > 0.0 && parsed.seconds <= 3600.0 && parsed.domain_id <= 232 &&
                     parsed.wait_s >= 0.0;
  return valid ? std::optional<SimArgs>(parsed) : std::nullopt;
}

int fail(const std::string& message) {
  std::fprintf(stderr, "navdevice sim: %s\n", message.c_str());
  return kExitError;
}

void print_status(double seconds, const nav::station::PlayerCounts& c, std::size_t stations) {
  std::printf("navdevice sim: %.0f s, written %lld poses, %lld frames, %lld truths; stations reading: %zu\n", seconds,
              static_cast<long long>(c.poses_written), static_cast<long long>(c.frames_written), static_cast<long long>(c.truths_written),
              stations);
  std::fflush(stdout);
}

}  // namespace

int run_sim(const std::vector<std::string>& arguments) {
  const std::optional<SimArgs> args = parse(arguments);
  if (!args) {
    std::fprintf(stderr, "usage: navdevice sim --scene FILE [--seconds S (0, 3600]] [--domain D] [--no-wait] [--wait-s S]\n");
    return kExitUsage;
  }
  nav::dds::install_stop_handlers();
  auto scene = nav::station::load_scene(args->scene_path);
  if (!scene.ok()) return fail(scene.error().describe());
  if (args->domain_id >= 0) scene.value().topics.domain_id = static_cast<std::uint32_t>(args->domain_id);
  const nav::station::Scene& s = scene.value();
  if (const nav::Status simulated = nav::station::check_simulated_devices(s); !simulated.ok()) return fail(simulated.error().describe());
  std::printf("navdevice sim: simulating %.0f s of the patient of scene '%s' (full-order liver, tracker, B-mode scanner) ...\n",
              args->seconds, s.station.name.c_str());
  std::fflush(stdout);
  auto liver = nav::station::make_station_liver(s);
  if (!liver.ok()) return fail(liver.error().describe());
  nav::station::WorldOptions world_options;
  world_options.duration_ns = static_cast<TimeNs>(args->seconds * 1e9);
  auto world = nav::station::simulate_world(liver.value(), s, nav::station::BreathingGeometry{}, world_options);
  if (!world.ok()) return fail(world.error().describe());

  // A running station publishes its health from its loop: the patient starts with the first one
  // (a recorder or a display reading the poses is not a station). The sink outlives the
  // participant whose listener fills it (made first, destroyed last).
  auto health = std::make_unique<nav::dds::RingSink<nav::dds::StationHealth, 4>>();
  auto node = nav::station::make_station_node(s.topics.domain_id, "navdevice_sim", nav::station::topic_names(s.topics), s.network);
  if (!node.ok()) return fail(node.error().describe());
  nav::dds::DdsNode& dds = *node.value();
  for (const nav::Status& status : {dds.advertise<nav::dds::ToolPose>(), dds.advertise<nav::dds::UltrasoundFrame>(),
                                    dds.advertise<nav::dds::GroundTruth>(), dds.subscribe(*health)})
    if (!status.ok()) return fail(status.error().describe());
  if (args->wait_for_station) {
    std::printf("navdevice sim: waiting up to %.0f s for a running station (its health) on domain %u ...\n", args->wait_s,
                s.topics.domain_id);
    std::fflush(stdout);
    nav::MonotonicClock waiting;
    const TimeNs give_up_ns = waiting.now_ns() + static_cast<TimeNs>(args->wait_s * 1e9);
    while (health->size() == 0) {
      if (nav::dds::stop_requested()) return 0;
      if (waiting.now_ns() > give_up_ns) return fail("no station ran on this domain within " + std::to_string(args->wait_s) + " s");
      waiting.sleep_until_ns(waiting.now_ns() + 10 * kNsPerMs);
    }
  }

  // The devices stamp on their clock: this host's monotonic clock less the scene's offset.
  nav::MonotonicClock clock;
  const TimeNs start_ns = clock.now_ns() + kStartDelayNs;
  nav::station::WorldPlayer player(world.value(), true, s.devices.tracker.tools);
  player.set_world_to_device_ns(start_ns - static_cast<TimeNs>(s.devices.clock.offset_ms * 1e6));
  TimeNs next_status_ns = kNsPerSecond;
  while (!nav::dds::stop_requested()) {
    const TimeNs now_ns = clock.now_ns() - start_ns;
    if (now_ns > world_options.duration_ns) break;
    player.play_until(now_ns, &dds, clock);
    if (now_ns >= next_status_ns) {
      print_status(1e-9 * static_cast<double>(next_status_ns), player.counts(), dds.matched(nav::dds::Topic::tool_pose));
      next_status_ns += kNsPerSecond;
    }
    clock.sleep_until_ns(clock.now_ns() + kPlayPeriodNs);
  }
  dds.wait_for_acknowledgments(kNsPerSecond);  // the last truths reach the evaluation
  std::printf("navdevice sim: %s after %.1f s\n", nav::dds::stop_requested() ? "stopped" : "done",
              1e-9 * static_cast<double>(clock.now_ns() - start_ns));
  print_status(1e-9 * static_cast<double>(clock.now_ns() - start_ns), player.counts(), dds.matched(nav::dds::Topic::tool_pose));
  return 0;
}

}  // namespace navdevice
