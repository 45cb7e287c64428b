// navdevice capture: the scanner's image as a frame grabber (or a camera) sees it, a video
// file or an image sequence, read through OpenCV's capture: each frame clipped to the scene's
// rectangle, grey, with the scene's pixel spacing, stamped at its grab on the scene's device
// clock, on the frame topic as the probe's. A grabber delivers at its own rate; a file or a
// sequence is paced at devices.ultrasound.rate_hz.
#include "capture_device.hpp"

#include <cstdio>
#include <optional>

#include "device_common.hpp"
#include "nav/dds/stop_request.hpp"
#include "nav/ultrasound/capture_source.hpp"

namespace navdevice {
namespace {

using nav::TimeNs;

constexpr const char* kUsage =
    "usage: navdevice capture --scene FILE [--source INDEX|VIDEO|PATTERN] [--seconds S] [--domain D] [--no-wait] "
    "[--wait-s S]\n"
    "  default: the scene's devices.ultrasound.source (kind: capture); --seconds 0 (default): to the end of the\n"
    "  stream or until stopped\n";

/// The command line of navdevice capture.
struct CaptureArgs {
  DeviceArgs device;
  std::string source;
};

std::optional<CaptureArgs> parse(const std::vector<std::string>& args) {
  CaptureArgs parsed;
  for (std::size_t i = 0; i < args.size(); ++i) {
    try {
      if (take_common_flag(args, i, parsed.device)) continue;
      const bool has_value = i + 1 < args.size();
      if (args[i] == "--source" && has_value)
        parsed.source = args[++i];
      else
        return std::nullopt;
    } catch (const std::exception&) {
      return std::nullopt;
    }
  }
  return common_flags_valid(parsed.device) ? std::optional<CaptureArgs>(parsed) : std::nullopt;
}

}  // namespace

int run_capture(const std::vector<std::string>& arguments) {
  const std::optional<CaptureArgs> args = parse(arguments);
  if (!args) {
    std::fprintf(stderr, "%s", kUsage);
    return kExitUsage;
  }
  nav::dds::install_stop_handlers();
  auto scene = load_device_scene(args->device);
  if (!scene.ok()) return fail("capture", scene.error().describe());
  const nav::station::Scene& s = scene.value();
  const nav::station::UltrasoundSettings& u = s.devices.ultrasound;
  if (args->source.empty() && u.kind != nav::station::UltrasoundKind::capture)
    return fail("capture",
                s.source_path + ": devices.ultrasound is not a capture source (kind: capture): give --source");
  const std::string source = args->source.empty() ? u.capture_source : args->source;
  nav::ultrasound::CaptureOptions options;
  options.probe_tool_id = s.devices.tracker.tools.probe;
  options.pixel_spacing_m = u.pixel_spacing_m;
  options.clip = {u.clip_px[0], u.clip_px[1], u.clip_px[2], u.clip_px[3]};
  DeviceClock clock(s.devices.clock);
  auto capture = nav::ultrasound::CaptureSource::open(source, options, clock);
  if (!capture.ok()) return fail("capture", capture.error().describe());
  const bool paced = !nav::station::is_device_index(source);
  char pace[64] = "at the grabber's rate";
  if (paced) std::snprintf(pace, sizeof pace, "paced at %.4g Hz", u.rate_hz);
  std::printf("navdevice capture: %s: frames at %.3f x %.3f mm per pixel, clipped to %u x %u at (%u, %u)%s; %s\n",
              source.c_str(), 1e3 * u.pixel_spacing_m[0], 1e3 * u.pixel_spacing_m[1], u.clip_px[2], u.clip_px[3],
              u.clip_px[0], u.clip_px[1], u.clip_px[2] == 0 ? " (the whole image)" : "", pace);
  std::fflush(stdout);

  auto device = open_device_node(s, "navdevice_capture");
  if (!device.ok()) return fail("capture", device.error().describe());
  nav::dds::DdsNode& dds = *device.value().node;
  if (const nav::Status advertised = dds.advertise<nav::dds::UltrasoundFrame>(); !advertised.ok())
    return fail("capture", advertised.error().describe());
  if (const int waited =
          wait_for_station(device.value(), args->device, s, "capture", {nav::dds::Topic::ultrasound_frame});
      waited != 0)
    return waited < 0 ? 0 : waited;

  const auto period_ns = static_cast<TimeNs>(1e9 / u.rate_hz);
  const TimeNs start_ns = clock.now_ns();
  const TimeNs end_ns = args->device.seconds > 0.0 ? start_ns + static_cast<TimeNs>(args->device.seconds * 1e9) : 0;
  TimeNs next_frame_ns = start_ns, next_status_ns = start_ns + nav::kNsPerSecond;
  bool ended = false;
  while (!nav::dds::stop_requested() && (end_ns == 0 || clock.now_ns() < end_ns)) {
    if (paced) clock.sleep_until_ns(next_frame_ns);
    next_frame_ns += period_ns;
    const auto published = capture.value()->publish_next(dds);
    if (!published.ok()) return fail("capture", published.error().describe());
    if (!published.value()) {
      ended = true;
      break;
    }
    if (clock.now_ns() >= next_status_ns) {
      std::printf("navdevice capture: %.0f s, %llu frames published; stations reading: %zu\n",
                  1e-9 * static_cast<double>(next_status_ns - start_ns),
                  static_cast<unsigned long long>(capture.value()->frames_read()),
                  dds.matched(nav::dds::Topic::ultrasound_frame));
      std::fflush(stdout);
      next_status_ns += nav::kNsPerSecond;
    }
  }
  dds.wait_for_acknowledgments(nav::kNsPerSecond);
  std::printf("navdevice capture: %s after %.1f s: %llu frames published\n",
              ended                        ? "end of the stream"
              : nav::dds::stop_requested() ? "stopped"
                                           : "done",
              1e-9 * static_cast<double>(clock.now_ns() - start_ns),
              static_cast<unsigned long long>(capture.value()->frames_read()));
  return 0;
}

}  // namespace navdevice
