// navdevice plusserver: a PLUS sequence (.mha / .nrrd) served over OpenIGTLink as a PlusServer
// serves its devices: every tracked transform of the recording as a TRANSFORM of its recorded
// name, every frame as an IMAGE (named as the scene's openigtlink.image, else "Image"), each
// stamped with the wall-clock time it is sent, at the recorded intervals (or --fast). It
// serves where the scene's bridge connects (openigtlink.plus.connect), or connects where the
// bridge listens (plus.listen). A bridge that goes away is waited for again; what is played
// meanwhile is not sent.
#include "plusserver_device.hpp"

#include <cstdio>
#include <optional>

#include "device_common.hpp"
#include "nav/dds/stop_request.hpp"
#include "nav/igtl/igtl_outputs.hpp"
#include "nav/igtl/igtl_stream.hpp"
#include "nav/igtl/wall_clock.hpp"
#include "nav/ultrasound/sequence_player.hpp"
#include "plus_device.hpp"

namespace navdevice {
namespace {

using nav::TimeNs;

constexpr const char* kUsage =
    "usage: navdevice plusserver --scene FILE [--recording FILE.mha|.nrrd] [--fast] [--seconds S] [--wait-s S]\n"
    "  serves the recording where the scene's openigtlink.plus says (its bridge connects to connect:,\n"
    "  or listens at listen:); --recording default: the scene's devices.ultrasound.recording\n";

/// The command line of navdevice plusserver.
struct ServerArgs {
  DeviceArgs device;
  std::string recording;
  bool fast = false;
};

std::optional<ServerArgs> parse(const std::vector<std::string>& args) {
  ServerArgs parsed;
  for (std::size_t i = 0; i < args.size(); ++i) {
    try {
      if (take_common_flag(args, i, parsed.device)) continue;
      if (args[i] == "--recording" && i + 1 < args.size())
        parsed.recording = args[++i];
      else if (args[i] == "--fast")
        parsed.fast = true;
      else
        return std::nullopt;
    } catch (const std::exception&) {
      return std::nullopt;
    }
  }
  return common_flags_valid(parsed.device) ? std::optional<ServerArgs>(parsed) : std::nullopt;
}

/// The bridge's end of the connection: accepted where it connects, or opened where it listens;
/// opened again (without waiting) when it was lost.
class BridgeLink {
 public:
  BridgeLink(std::optional<nav::igtl::Listener> listener, nav::igtl::Endpoint bridge)
      : listener_(std::move(listener)), bridge_(std::move(bridge)) {}

  /// Waits up to `timeout_ns` for a connection when there is none (connecting at most once a
  /// second); whether there is one.
  bool connected(TimeNs timeout_ns) {
    if (stream_ && stream_->open()) return true;
    if (!listener_ && clock_.now_ns() < retry_at_ns_) return false;
    auto opened = listener_ ? listener_->accept(timeout_ns) : nav::igtl::MessageStream::connect(bridge_, timeout_ns);
    if (!opened) {
      retry_at_ns_ = clock_.now_ns() + nav::kNsPerSecond;
      return false;
    }
    stream_.emplace(std::move(opened).value());
    std::printf("navdevice plusserver: bridge connected: %s\n", stream_->peer().c_str());
    std::fflush(stdout);
    return true;
  }

  /// Sends `message` when connected; a failed send drops the connection.
  void send(const std::vector<std::uint8_t>& message) {
    if (!connected(0)) return;
    if (const nav::Status sent = stream_->write(message); !sent) {
      std::printf("navdevice plusserver: bridge gone: %s\n", sent.error().describe().c_str());
      std::fflush(stdout);
      stream_.reset();
      return;
    }
    ++sent_;
  }

  std::uint64_t sent() const noexcept { return sent_; }

 private:
  std::optional<nav::igtl::Listener> listener_;
  nav::igtl::Endpoint bridge_;
  std::optional<nav::igtl::MessageStream> stream_;
  nav::MonotonicClock clock_;
  TimeNs retry_at_ns_ = 0;
  std::uint64_t sent_ = 0;
};

}  // namespace

int run_plusserver(const std::vector<std::string>& arguments) {
  const std::optional<ServerArgs> args = parse(arguments);
  if (!args) {
    std::fprintf(stderr, "%s", kUsage);
    return kExitUsage;
  }
  nav::dds::install_stop_handlers();
  auto scene = load_device_scene(args->device);
  if (!scene.ok()) return fail("plusserver", scene.error().describe());
  const nav::station::Scene& s = scene.value();
  if (!s.openigtlink || !s.openigtlink->plus)
    return fail("plusserver", s.source_path + ": openigtlink.plus: the scene names no PlusServer address");
  const nav::station::OpenIgtlinkSettings& igtl = *s.openigtlink;
  auto sequence = scene_recording(s, args->recording);
  if (!sequence.ok()) return fail("plusserver", sequence.error().describe());
  const nav::ultrasound::PlusSequence& q = sequence.value();

  const nav::igtl::Endpoint address{igtl.plus->host, igtl.plus->port};
  std::optional<nav::igtl::Listener> listener;
  if (!igtl.plus_connects) {  // the bridge connects: serve here
    auto listening = nav::igtl::Listener::listen(address);
    if (!listening) return fail("plusserver", listening.error().describe());
    listener.emplace(std::move(listening).value());
  }
  const std::string image_device = igtl.image.empty() ? "Image" : igtl.image;
  std::printf("navdevice plusserver: %s: %zu frames of %u x %u at %.3f x %.3f mm, %zu transforms, as %s; %s %s:%d\n",
              q.path.c_str(), q.frames_read, q.width_px, q.height_px, q.spacing_mm[0], q.spacing_mm[1],
              q.transforms.size(), image_device.c_str(), listener ? "serving on" : "connecting to",
              address.host.c_str(), listener ? listener->port() : address.port);
  std::fflush(stdout);

  BridgeLink bridge(std::move(listener), address);
  nav::MonotonicClock clock;
  const TimeNs wait_until_ns = clock.now_ns() + static_cast<TimeNs>(args->device.wait_s * 1e9);
  while (!bridge.connected(100 * nav::kNsPerMs)) {
    if (nav::dds::stop_requested()) return 0;
    if (clock.now_ns() > wait_until_ns)
      return fail("plusserver", "no bridge connected within " + std::to_string(args->device.wait_s) + " s");
    if (igtl.plus_connects) clock.sleep_until_ns(clock.now_ns() + 100 * nav::kNsPerMs);  // else accept() waited
  }

  nav::ultrasound::PlayOptions options;
  options.tools.clear();
  for (const nav::ultrasound::TransformTrack& track : q.transforms) options.tools.push_back({track.name, 0});
  options.as_fast_as_possible = args->fast;
  const TimeNs start_ns = clock.now_ns();
  options.after_frame = [&](std::size_t) {
    const bool in_time =
        args->device.seconds == 0.0 || clock.now_ns() - start_ns < static_cast<TimeNs>(args->device.seconds * 1e9);
    return in_time && !nav::dds::stop_requested();
  };
  const auto played = nav::ultrasound::play_sequence(
      q, options, clock,
      {.transform =
           [&](const nav::ultrasound::ToolTrack&, const nav::ultrasound::TransformTrack& track, std::size_t index,
               TimeNs) {
             const nav::dds::ToolPose pose =
                 nav::ultrasound::make_pose_sample(track.matrices_mm[index], track.name, 0, index, 0);
             bridge.send(nav::igtl::pack_transform(track.name, pose.orientation_wxyz, pose.position_m,
                                                   nav::igtl::wall_now_ns()));
           },
       .image =
           [&](std::size_t index, TimeNs) {
             bridge.send(nav::igtl::pack_image(image_device, q.width_px, q.height_px,
                                               {q.frame(index), q.frame_pixels()}, q.spacing_mm,
                                               nav::igtl::wall_now_ns()));
           }});
  if (!played.ok()) return fail("plusserver", played.error().describe());
  std::printf("navdevice plusserver: %s after %.1f s: %zu of %zu frames played, %llu messages sent\n",
              nav::dds::stop_requested() ? "stopped" : "done", 1e-9 * static_cast<double>(clock.now_ns() - start_ns),
              played.value(), q.frames_read, static_cast<unsigned long long>(bridge.sent()));
  return 0;
}

}  // namespace navdevice
