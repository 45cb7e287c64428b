// navdevice plus: a PLUS sequence (.mha / .nrrd, as PLUS's sequence capture writes it) played
// as the station's ultrasound scanner and tracker: every frame on the scene's frame topic with
// its own size and spacing, every valid tracked transform of a mapped tool on its pose topic,
// at the recorded intervals (or as fast as asked), stamped on this host's monotonic clock less
// the scene's device clock offset, as a device on that clock would stamp them.
#include "plus_device.hpp"

#include <cstdio>
#include <optional>
#include <utility>

#include "device_common.hpp"
#include "nav/dds/stop_request.hpp"
#include "nav/ultrasound/plus_sequence.hpp"
#include "nav/ultrasound/sequence_player.hpp"

namespace navdevice {
namespace {

using nav::TimeNs;

constexpr const char* kUsage =
    "usage: navdevice plus --scene FILE [--recording FILE.mha|.nrrd] [--fast] [--transform NAME=ROLE]...\n"
    "                      [--seconds S] [--domain D] [--no-wait] [--wait-s S]\n"
    "  --recording   default: the scene's devices.ultrasound.recording (kind: plus)\n"
    "  --transform   a recorded transform played as a tool: ROLE needle, probe or respiratory (ids from\n"
    "                devices.tracker.tools); default ProbeToTracker=probe and StylusToTracker=needle,\n"
    "                each where the recording has it\n";

/// The command line of navdevice plus.
struct PlusArgs {
  DeviceArgs device;
  std::string recording;
  bool fast = false;
  std::vector<std::pair<std::string, std::string>> transforms;  ///< recorded name, role
};

std::optional<PlusArgs> parse(const std::vector<std::string>& args) {
  PlusArgs parsed;
  for (std::size_t i = 0; i < args.size(); ++i) {
    try {
      if (take_common_flag(args, i, parsed.device)) continue;
      const bool has_value = i + 1 < args.size();
      if (args[i] == "--recording" && has_value) {
        parsed.recording = args[++i];
      } else if (args[i] == "--fast") {
        parsed.fast = true;
      } else if (args[i] == "--transform" && has_value) {
        const std::string mapping = args[++i];
        const std::size_t equals = mapping.find('=');
        if (equals == std::string::npos || equals == 0 || equals + 1 == mapping.size()) return std::nullopt;
        parsed.transforms.emplace_back(mapping.substr(0, equals), mapping.substr(equals + 1));
      } else {
        return std::nullopt;
      }
    } catch (const std::exception&) {
      return std::nullopt;
    }
  }
  return common_flags_valid(parsed.device) ? std::optional<PlusArgs>(parsed) : std::nullopt;
}

/// The tracks to play: the explicit mappings (each must be in the recording), or the default
/// ones the recording has. An Error names the mapping at fault.
nav::Result<std::vector<nav::ultrasound::ToolTrack>> tool_tracks(const PlusArgs& args,
                                                                 const nav::ultrasound::PlusSequence& sequence,
                                                                 const nav::station::ToolIds& tools) {
  std::vector<nav::ultrasound::ToolTrack> tracks;
  const bool defaults = args.transforms.empty();
  const std::vector<std::pair<std::string, std::string>> wanted =
      defaults
          ? std::vector<std::pair<std::string, std::string>>{{"ProbeToTracker", "probe"}, {"StylusToTracker", "needle"}}
          : args.transforms;
  for (const auto& [name, role] : wanted) {
    const std::optional<std::uint32_t> id = nav::station::tool_id_of_role(tools, role);
    if (!id)
      return nav::Error{.message = "unknown role '" + role +
                                   "' (needle, probe, respiratory, or reference when the scene declares one)",
                        .field = "--transform " + name + "=" + role};
    if (sequence.find_transform(name) == nullptr) {
      if (defaults) continue;
      return nav::Error{.message = "the recording has no transform '" + name + "'",
                        .file = sequence.path,
                        .field = "--transform " + name + "=" + role};
    }
    tracks.push_back({name, *id});
  }
  return tracks;
}

}  // namespace

nav::Result<nav::ultrasound::PlusSequence> scene_recording(const nav::station::Scene& scene,
                                                           const std::string& recording) {
  const nav::station::UltrasoundSettings& ultrasound = scene.devices.ultrasound;
  const bool scene_plays = ultrasound.kind == nav::station::UltrasoundKind::plus;
  if (recording.empty() && !scene_plays)
    return nav::Error{.message = "devices.ultrasound is not a PLUS recording (kind: plus): give --recording FILE",
                      .file = scene.source_path};
  auto sequence = nav::ultrasound::read_plus_sequence(recording.empty() ? ultrasound.recording_path : recording);
  if (sequence.ok() && scene_plays && ultrasound.recording_pixel_spacing_m)
    sequence.value().spacing_mm = {1e3 * (*ultrasound.recording_pixel_spacing_m)[0],
                                   1e3 * (*ultrasound.recording_pixel_spacing_m)[1]};
  return sequence;
}

int run_plus(const std::vector<std::string>& arguments) {
  const std::optional<PlusArgs> args = parse(arguments);
  if (!args) {
    std::fprintf(stderr, "%s", kUsage);
    return kExitUsage;
  }
  nav::dds::install_stop_handlers();
  auto scene = load_device_scene(args->device);
  if (!scene.ok()) return fail("plus", scene.error().describe());
  const nav::station::Scene& s = scene.value();
  auto sequence = scene_recording(s, args->recording);
  if (!sequence.ok()) return fail("plus", sequence.error().describe());
  nav::ultrasound::PlusSequence& q = sequence.value();
  auto tracks = tool_tracks(*args, q, s.devices.tracker.tools);
  if (!tracks.ok()) return fail("plus", tracks.error().describe());
  std::printf("navdevice plus: %s: %zu frames of %u x %u at %.3f x %.3f mm, %.1f s recorded; playing", q.path.c_str(),
              q.frames_read, q.width_px, q.height_px, q.spacing_mm[0], q.spacing_mm[1],
              q.timestamps_s.empty() ? 0.0 : q.timestamps_s.back() - q.timestamps_s.front());
  for (const nav::ultrasound::ToolTrack& t : tracks.value())
    std::printf(" %s as tool %u,", t.transform_name.c_str(), t.tool_id);
  std::printf(" %s\n", args->fast ? "as fast as possible" : "at the recorded intervals");
  std::fflush(stdout);

  auto device = open_device_node(s, "navdevice_plus");
  if (!device.ok()) return fail("plus", device.error().describe());
  nav::dds::DdsNode& dds = *device.value().node;
  for (const nav::Status& status : {dds.advertise<nav::dds::ToolPose>(), dds.advertise<nav::dds::UltrasoundFrame>()})
    if (!status.ok()) return fail("plus", status.error().describe());
  if (const int waited = wait_for_station(device.value(), args->device, s, "plus",
                                          {nav::dds::Topic::tool_pose, nav::dds::Topic::ultrasound_frame});
      waited != 0)
    return waited < 0 ? 0 : waited;

  DeviceClock clock(s.devices.clock);
  const TimeNs start_ns = clock.now_ns();
  TimeNs next_status_ns = start_ns + nav::kNsPerSecond;
  nav::ultrasound::PlayOptions options;
  options.tools = tracks.value();
  options.probe_tool_id = s.devices.tracker.tools.probe;
  options.as_fast_as_possible = args->fast;
  options.after_frame = [&](std::size_t played) {
    if (clock.now_ns() >= next_status_ns) {
      std::printf("navdevice plus: %.0f s, %zu of %zu frames played; stations reading: %zu\n",
                  1e-9 * static_cast<double>(next_status_ns - start_ns), played, q.frames_read,
                  dds.matched(nav::dds::Topic::ultrasound_frame));
      std::fflush(stdout);
      next_status_ns += nav::kNsPerSecond;
    }
    const bool in_time =
        args->device.seconds == 0.0 || clock.now_ns() - start_ns < static_cast<TimeNs>(args->device.seconds * 1e9);
    return in_time && !nav::dds::stop_requested();
  };
  const auto played = nav::ultrasound::play_sequence(dds, q, options, clock);
  if (!played.ok()) return fail("plus", played.error().describe());
  dds.wait_for_acknowledgments(nav::kNsPerSecond);
  std::printf("navdevice plus: %s after %.1f s: %zu of %zu frames played\n",
              nav::dds::stop_requested() ? "stopped" : "done", 1e-9 * static_cast<double>(clock.now_ns() - start_ns),
              played.value(), q.frames_read);
  return 0;
}

}  // namespace navdevice
