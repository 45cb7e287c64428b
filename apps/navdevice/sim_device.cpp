#include "sim_device.hpp"

#include <algorithm>
#include <cstdio>
#include <optional>

#include "device_common.hpp"
#include "nav/core/clock.hpp"
#include "nav/dds/stop_request.hpp"
#include "nav/station/simulated_world.hpp"
#include "nav/station/station_liver.hpp"
#include "nav/station/tracker_registration.hpp"
#include "nav/station/world_player.hpp"

namespace navdevice {
namespace {

using nav::kNsPerMs;
using nav::kNsPerSecond;
using nav::TimeNs;

constexpr TimeNs kPlayPeriodNs = kNsPerMs / 2;
constexpr TimeNs kStartDelayNs = 20 * kNsPerMs;  // from the station's match to world time 0

constexpr double kDefaultSeconds = 60.0;
constexpr double kMaxSeconds = 4 * 3600.0;
/// A longer run simulates this much of the patient (the needle has stopped by then and the
/// world is periodic) and repeats its last period: a soak's patient costs what a minute's does.
constexpr double kRecordedSeconds = 60.0;

void print_status(double seconds, const nav::station::PlayerCounts& c, std::size_t stations) {
  std::printf("navdevice sim: %.0f s, written %lld poses, %lld frames, %lld truths; stations reading: %zu\n", seconds,
              static_cast<long long>(c.poses_written), static_cast<long long>(c.frames_written),
              static_cast<long long>(c.truths_written), stations);
  std::fflush(stdout);
}

}  // namespace

int run_sim(const std::vector<std::string>& arguments) {
  std::optional<DeviceArgs> args = parse_common_flags(arguments);
  if (args && args->seconds == 0.0) args->seconds = kDefaultSeconds;
  if (!args || args->seconds > kMaxSeconds) {
    std::fprintf(stderr,
                 "usage: navdevice sim --scene FILE [--seconds S (0, 14400]] [--domain D] [--no-wait] [--wait-s S]\n");
    return kExitUsage;
  }
  nav::dds::install_stop_handlers();
  auto scene = load_device_scene(*args);
  if (!scene.ok()) return fail("sim", scene.error().describe());
  const nav::station::Scene& s = scene.value();
  if (const nav::Status simulated = nav::station::check_simulated_devices(s); !simulated.ok())
    return fail("sim", simulated.error().describe());
  const double recorded_s = std::min(args->seconds, kRecordedSeconds);
  nav::station::WorldOptions world_options;
  world_options.duration_ns = static_cast<TimeNs>(recorded_s * 1e9);
  const TimeNs period_ns = nav::station::world_period_ns(world_options);
  std::printf(
      "navdevice sim: simulating %.0f s of the patient of scene '%s' (full-order liver, tracker, B-mode scanner)",
      recorded_s, s.station.name.c_str());
  if (args->seconds > recorded_s)
    std::printf("; its last %.0f s repeat to %.0f s", 1e-9 * static_cast<double>(period_ns), args->seconds);
  std::printf(" ...\n");
  std::fflush(stdout);
  auto liver = nav::station::make_station_liver(s);
  if (!liver.ok()) return fail("sim", liver.error().describe());
  auto world = nav::station::simulate_world(liver.value(), s, nav::station::BreathingGeometry{}, world_options);
  if (!world.ok()) return fail("sim", world.error().describe());

  auto device = open_device_node(s, "navdevice_sim");
  if (!device.ok()) return fail("sim", device.error().describe());
  nav::dds::DdsNode& dds = *device.value().node;
  for (const nav::Status& status : {dds.advertise<nav::dds::ToolPose>(), dds.advertise<nav::dds::UltrasoundFrame>(),
                                    dds.advertise<nav::dds::GroundTruth>()})
    if (!status.ok()) return fail("sim", status.error().describe());
  if (const int waited = wait_for_station(device.value(), *args, s, "sim",
                                          {nav::dds::Topic::tool_pose, nav::dds::Topic::ultrasound_frame});
      waited != 0)
    return waited < 0 ? 0 : waited;

  // The devices stamp on their clock: this host's monotonic clock less the scene's offset.
  nav::MonotonicClock clock;
  const TimeNs start_ns = clock.now_ns() + kStartDelayNs;
  auto reference_from_model = nav::station::scene_reference_from_model(s);
  if (!reference_from_model.ok()) return fail("sim", reference_from_model.error().describe());
  const nav::station::TrackerSettings& t = s.devices.tracker;
  nav::station::WorldPlayer player(
      world.value(), true,
      nav::station::simulated_tracker(t.tools, t.tracker_from_reference, reference_from_model.value()));
  player.set_world_to_device_ns(start_ns - static_cast<TimeNs>(s.devices.clock.offset_ms * 1e6));
  if (args->seconds > recorded_s) player.repeat_last(period_ns);
  const auto run_ns = static_cast<TimeNs>(args->seconds * 1e9);
  TimeNs next_status_ns = kNsPerSecond;
  while (!nav::dds::stop_requested()) {
    const TimeNs now_ns = clock.now_ns() - start_ns;
    if (now_ns > run_ns) break;
    player.play_until(now_ns, &dds, clock);
    if (now_ns >= next_status_ns) {
      print_status(1e-9 * static_cast<double>(next_status_ns), player.counts(),
                   dds.matched(nav::dds::Topic::tool_pose));
      next_status_ns += kNsPerSecond;
    }
    clock.sleep_until_ns(clock.now_ns() + kPlayPeriodNs);
  }
  dds.wait_for_acknowledgments(kNsPerSecond);  // the last truths reach the evaluation
  std::printf("navdevice sim: %s after %.1f s\n", nav::dds::stop_requested() ? "stopped" : "done",
              1e-9 * static_cast<double>(clock.now_ns() - start_ns));
  print_status(1e-9 * static_cast<double>(clock.now_ns() - start_ns), player.counts(),
               dds.matched(nav::dds::Topic::tool_pose));
  return 0;
}

}  // namespace navdevice
