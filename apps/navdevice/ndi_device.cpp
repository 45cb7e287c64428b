// navdevice ndi: an NDI tracker (Polaris, Aurora, Vega: the combined API over a serial line or
// TCP) as the station's tracker. On a serial line it negotiates the scene's rate (baud), loads
// the passive tools' definitions (rom_files), initialises the device and every port handle, polls BX
// replies at the scene's rate, and publishes each pose of a port handle the scene maps to a
// tool (devices.tracker.port_handles) as that tool's sample, stamped with the request's time
// on the scene's device clock; on SIGINT or SIGTERM it stops tracking (TSTOP) and exits.
#include "ndi_device.hpp"

#include <cstdio>
#include <map>
#include <optional>

#include "device_common.hpp"
#include "nav/dds/stop_request.hpp"
#include "nav/trackers/ndi_tracker.hpp"
#include "nav/trackers/pose_publisher.hpp"

namespace navdevice {
namespace {

using nav::TimeNs;

constexpr const char* kUsage =
    "usage: navdevice ndi --scene FILE [--serial DEVICE | --tcp HOST:PORT] [--seconds S] [--domain D] [--no-wait] "
    "[--wait-s S]\n"
    "  default: the scene's devices.tracker (kind: ndi) serial device or host and port; --seconds 0 (default)\n"
    "  tracks until stopped\n";

/// The command line of navdevice ndi.
struct NdiArgs {
  DeviceArgs device;
  std::string serial, host;
  int port = 0;
};

std::optional<NdiArgs> parse(const std::vector<std::string>& args) {
  NdiArgs parsed;
  for (std::size_t i = 0; i < args.size(); ++i) {
    try {
      if (take_common_flag(args, i, parsed.device)) continue;
      const bool has_value = i + 1 < args.size();
      if (args[i] == "--serial" && has_value) {
        parsed.serial = args[++i];
      } else if (args[i] == "--tcp" && has_value) {
        const std::string address = args[++i];
        const std::size_t colon = address.rfind(':');
        if (colon == std::string::npos || colon == 0) return std::nullopt;
        parsed.host = address.substr(0, colon);
        parsed.port = std::stoi(address.substr(colon + 1));
      } else {
        return std::nullopt;
      }
    } catch (const std::exception&) {
      return std::nullopt;
    }
  }
  const bool valid = common_flags_valid(parsed.device) && (parsed.serial.empty() || parsed.host.empty()) &&
                     (parsed.host.empty() || (parsed.port >= 1 && parsed.port <= 65535));
  return valid ? std::optional<NdiArgs>(parsed) : std::nullopt;
}

/// Where the device is: the flags, else the scene's; "" and an Error when neither names one.
nav::Result<nav::trackers::ndi::Connection> connect(const NdiArgs& args, const nav::station::Scene& scene,
                                                    std::string& where) {
  const nav::station::TrackerSettings& t = scene.devices.tracker;
  const bool from_flags = !args.serial.empty() || !args.host.empty();
  if (!from_flags && t.kind != nav::station::TrackerKind::ndi)
    return nav::Error{.message = scene.source_path +
                                 ": devices.tracker is not an NDI tracker (kind: ndi): give --serial or --tcp"};
  const std::string serial = from_flags ? args.serial : t.serial_device;
  const std::string host = from_flags ? args.host : t.host;
  const int port = from_flags ? args.port : t.port;
  where = serial.empty() ? host + ":" + std::to_string(port) : serial;
  return serial.empty() ? nav::trackers::ndi::Connection::open_tcp(host, port)
                        : nav::trackers::ndi::Connection::open_serial(serial);
}

/// Polls made and samples of handles the scene does not map, for the status lines.
struct PollCounts {
  std::uint64_t polls = 0, unmapped = 0;
};

void print_status(double seconds, const PollCounts& polls, const nav::trackers::PublishCounts& c,
                  std::size_t stations) {
  std::printf(
      "navdevice ndi: %.0f s, %llu polls, %llu poses published, %llu tool samples without a pose, %llu refused, "
      "%llu of unmapped handles; stations reading: %zu\n",
      seconds, static_cast<unsigned long long>(polls.polls), static_cast<unsigned long long>(c.published),
      static_cast<unsigned long long>(c.without_pose), static_cast<unsigned long long>(c.refused),
      static_cast<unsigned long long>(polls.unmapped), stations);
  std::fflush(stdout);
}

}  // namespace

int run_ndi(const std::vector<std::string>& arguments) {
  const std::optional<NdiArgs> args = parse(arguments);
  if (!args) {
    std::fprintf(stderr, "%s", kUsage);
    return kExitUsage;
  }
  nav::dds::install_stop_handlers();
  auto scene = load_device_scene(args->device);
  if (!scene.ok()) return fail("ndi", scene.error().describe());
  const nav::station::Scene& s = scene.value();
  const nav::station::TrackerSettings& t = s.devices.tracker;
  // Passive tools: their definitions go into the device, which gives them their port handles.
  std::vector<nav::station::ToolRole> roles = nav::station::tool_roles(t.tools, t.port_handles);
  std::vector<std::string> definitions;
  std::vector<std::size_t> passive_roles;
  for (std::size_t k = 0; k < roles.size(); ++k) {
    const auto file = t.rom_files.find(roles[k].role);
    if (file == t.rom_files.end()) continue;
    auto definition = nav::trackers::ndi::read_tool_definition(file->second);
    if (!definition.ok()) return fail("ndi", definition.error().describe());
    definitions.push_back(std::move(definition).value());
    passive_roles.push_back(k);
  }
  std::string where;
  auto connection = connect(*args, s, where);
  if (!connection.ok()) return fail("ndi", connection.error().describe());
  if (!connection.value().path().empty()) {  // a serial line: from 9600 to the scene's rate
    if (const nav::Status negotiated = nav::trackers::ndi::negotiate_serial(connection.value(), t.baud);
        !negotiated.ok())
      return fail("ndi", negotiated.error().describe());  // names the line
  }
  auto tracker = nav::trackers::ndi::NdiTracker::start(std::move(connection).value(), definitions);
  if (!tracker.ok()) return fail("ndi", where + ": " + tracker.error().describe());
  for (std::size_t i = 0; i < passive_roles.size(); ++i)
    roles[passive_roles[i]].device_id = tracker.value().passive_handles()[i];
  std::map<std::uint32_t, std::uint32_t> tool_of_handle;
  for (const nav::station::ToolRole& r : roles) tool_of_handle[r.device_id] = r.tool_id;
  std::printf("navdevice ndi: %s: %zu port handles enabled; %s; polling at %.0f Hz\n", where.c_str(),
              tracker.value().handles().size(), describe_roles(roles, "handle").c_str(), s.devices.tracker.rate_hz);
  std::fflush(stdout);

  auto device = open_device_node(s, "navdevice_ndi");
  if (!device.ok()) return fail("ndi", device.error().describe());
  nav::dds::DdsNode& dds = *device.value().node;
  auto publisher = nav::trackers::PosePublisher::create(dds, "tracker", tool_frames(roles));
  if (!publisher.ok()) return fail("ndi", publisher.error().describe());
  if (const int waited = wait_for_station(device.value(), args->device, s, "ndi", {nav::dds::Topic::tool_pose});
      waited != 0) {
    (void)tracker.value().stop();
    return waited < 0 ? 0 : waited;
  }

  DeviceClock clock(s.devices.clock);
  const auto period_ns = static_cast<TimeNs>(1e9 / s.devices.tracker.rate_hz);
  const TimeNs start_ns = clock.now_ns();
  const TimeNs end_ns = args->device.seconds > 0.0 ? start_ns + static_cast<TimeNs>(args->device.seconds * 1e9) : 0;
  TimeNs next_poll_ns = start_ns, next_status_ns = start_ns + nav::kNsPerSecond;
  PollCounts counts;
  int exit_code = 0;
  while (!nav::dds::stop_requested() && (end_ns == 0 || next_poll_ns < end_ns)) {
    clock.sleep_until_ns(next_poll_ns);
    auto samples = tracker.value().poll(nav::trackers::ndi::ReplyFormat::bx, next_poll_ns);
    if (!samples.ok()) {
      exit_code = fail("ndi", where + ": " + samples.error().describe());
      break;
    }
    ++counts.polls;
    for (nav::trackers::TrackerSample sample : samples.value()) {
      const auto mapped = tool_of_handle.find(sample.tool_id);
      if (mapped == tool_of_handle.end()) {
        ++counts.unmapped;
        continue;
      }
      sample.tool_id = mapped->second;
      publisher.value().publish(sample);
    }
    if (clock.now_ns() >= next_status_ns) {
      print_status(1e-9 * static_cast<double>(next_status_ns - start_ns), counts, publisher.value().counts(),
                   dds.matched(nav::dds::Topic::tool_pose));
      next_status_ns += nav::kNsPerSecond;
    }
    next_poll_ns += period_ns;
  }
  const nav::Status stopped = tracker.value().stop();
  if (!stopped.ok() && exit_code == 0) exit_code = fail("ndi", where + ": " + stopped.error().describe());
  dds.wait_for_acknowledgments(nav::kNsPerSecond);
  std::printf("navdevice ndi: %s after %.1f s\n",
              nav::dds::stop_requested() ? "stopped"
              : exit_code == 0           ? "done"
                                         : "failed",
              1e-9 * static_cast<double>(clock.now_ns() - start_ns));
  print_status(1e-9 * static_cast<double>(clock.now_ns() - start_ns), counts, publisher.value().counts(),
               dds.matched(nav::dds::Topic::tool_pose));
  return exit_code;
}

}  // namespace navdevice
