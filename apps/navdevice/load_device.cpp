// navdevice load: what else a busy station host does, for soak runs. Pinned to the scene's
// I/O core, it publishes poses and B-mode frames at FACTOR times the scene's tracker and
// scanner rates on topics of its own (load/tool_pose, load/ultrasound_frame), reads them back,
// and filters every frame it reads as an image pipeline would (blur, Otsu threshold, contours).
// The I/O core's work and the host's DDS traffic grow; the station's topics carry none of it.
#include "load_device.hpp"

#include <algorithm>
#include <cstdio>
#include <memory>
#include <optional>

#include <opencv2/imgproc.hpp>

#include "device_common.hpp"
#include "nav/dds/stop_request.hpp"
#include "nav/station/realtime_thread.hpp"
#include "nav/station/station_dds.hpp"
#include "nav/station/tumour_observer.hpp"

namespace navdevice {
namespace {

using nav::kNsPerSecond;
using nav::TimeNs;

constexpr const char* kUsage =
    "usage: navdevice load --scene FILE [--factor F] [--seconds S] [--domain D]\n"
    "  F (default 4) times the scene's tracker and scanner rates, on topics load/tool_pose and\n"
    "  load/ultrasound_frame, on the scene's I/O core; --seconds 0 (default): until stopped\n";
constexpr double kDefaultFactor = 4.0;
constexpr std::uint32_t kTools = 3;   // a tracker sample: the needle, probe and respiratory markers
constexpr int kDefaultFramePx = 256;  // a frame's side when the scene's scanner has no simulated size
constexpr TimeNs kPollPeriodNs = nav::kNsPerMs / 2;

struct LoadArgs {
  DeviceArgs device;
  double factor = kDefaultFactor;
};

std::optional<LoadArgs> parse(const std::vector<std::string>& args) {
  LoadArgs parsed;
  parsed.device.wait_for_station = false;
  for (std::size_t i = 0; i < args.size(); ++i) {
    try {
      if (take_common_flag(args, i, parsed.device)) continue;
      if (args[i] == "--factor" && i + 1 < args.size())
        parsed.factor = std::stod(args[++i]);
      else
        return std::nullopt;
    } catch (const std::exception&) {
      return std::nullopt;
    }
  }
  if (!common_flags_valid(parsed.device) || !(parsed.factor > 0.0 && parsed.factor <= 100.0)) return std::nullopt;
  return parsed;
}

/// The frames read back, filtered as an image pipeline would; counts and times them.
class FramePipeline {
 public:
  FramePipeline(int width_px, int height_px)
      : blurred_(height_px, width_px, CV_8UC1), mask_(height_px, width_px, CV_8UC1) {}

  void process(const nav::dds::UltrasoundFrame& frame, const nav::MonotonicClock& clock) {
    const TimeNs start_ns = clock.now_ns();
    const cv::Mat image(static_cast<int>(frame.height_px), static_cast<int>(frame.width_px), CV_8UC1,
                        const_cast<std::uint8_t*>(frame.pixels.data()));
    cv::GaussianBlur(image, blurred_, cv::Size(7, 7), 2.0);
    cv::threshold(blurred_, mask_, 0, 255, cv::THRESH_BINARY | cv::THRESH_OTSU);
    cv::findContours(mask_, contours_, cv::RETR_EXTERNAL, cv::CHAIN_APPROX_SIMPLE);
    busy_ns_ += clock.now_ns() - start_ns;
    ++frames_;
  }
  std::int64_t frames() const { return frames_; }
  double busy_ms() const { return 1e-6 * static_cast<double>(busy_ns_); }

 private:
  cv::Mat blurred_, mask_;
  std::vector<std::vector<cv::Point>> contours_;
  std::int64_t frames_ = 0;
  TimeNs busy_ns_ = 0;
};

/// A frame of the scanner's size with speckle-like content, so that the filters have work.
std::unique_ptr<nav::dds::UltrasoundFrame> load_frame(const nav::station::Scene& scene) {
  auto frame = std::make_unique<nav::dds::UltrasoundFrame>();
  const auto imaging = nav::station::scene_probe_imaging(scene);
  frame->width_px = imaging.ok() ? static_cast<std::uint32_t>(imaging.value().geometry.width_px) : kDefaultFramePx;
  frame->height_px = imaging.ok() ? static_cast<std::uint32_t>(imaging.value().geometry.height_px) : kDefaultFramePx;
  frame->pixel_spacing_m = {2e-4, 2e-4};
  frame->depth_m = 2e-4 * frame->height_px;
  std::uint32_t state = 12345u;
  for (std::size_t i = 0; i < frame->pixel_count(); ++i) {
    state = state * 1664525u + 1013904223u;
    frame->pixels[i] = static_cast<std::uint8_t>(state >> 24);
  }
  return frame;
}

}  // namespace

int run_load(const std::vector<std::string>& arguments) {
  const std::optional<LoadArgs> args = parse(arguments);
  if (!args) {
    std::fputs(kUsage, stderr);
    return kExitUsage;
  }
  nav::dds::install_stop_handlers();
  auto scene = load_device_scene(args->device);
  if (!scene.ok()) return fail("load", scene.error().describe());
  const nav::station::Scene& s = scene.value();
  // Pinned first: the participant's threads, made next, inherit the I/O core.
  const nav::station::SetupStep pinned = nav::station::pin_to_core(s.station.io_core);
  nav::dds::TopicNames names{};
  names[static_cast<std::size_t>(nav::dds::Topic::tool_pose)] = "load/tool_pose";
  names[static_cast<std::size_t>(nav::dds::Topic::ultrasound_frame)] = "load/ultrasound_frame";
  auto node = nav::station::make_station_node(s.topics.domain_id, "navdevice_load", names, s.network,
                                              nav::station::Role::devices);
  if (!node.ok()) return fail("load", node.error().describe());
  auto poses_read = std::make_unique<nav::dds::RingSink<nav::dds::ToolPose, 256>>();
  auto frames_read = std::make_unique<nav::dds::RingSink<nav::dds::UltrasoundFrame, 4>>();
  nav::dds::DdsNode& dds = *node.value();
  for (const nav::Status& status : {dds.advertise<nav::dds::ToolPose>(), dds.advertise<nav::dds::UltrasoundFrame>(),
                                    dds.subscribe(*poses_read), dds.subscribe(*frames_read)})
    if (!status.ok()) return fail("load", status.error().describe());

  auto frame = load_frame(s);
  auto received = std::make_unique<nav::dds::UltrasoundFrame>();
  FramePipeline pipeline(static_cast<int>(frame->width_px), static_cast<int>(frame->height_px));
  const TimeNs pose_period_ns = static_cast<TimeNs>(1e9 / (args->factor * s.devices.tracker.rate_hz));
  const TimeNs frame_period_ns = static_cast<TimeNs>(1e9 / (args->factor * s.devices.ultrasound.rate_hz));
  std::printf(
      "navdevice load: %.3g x the scene's rates: %u poses every %.2f ms, a %u x %u frame every %.2f ms, on core %d "
      "(%s)\n",
      args->factor, kTools, 1e-6 * static_cast<double>(pose_period_ns), frame->width_px, frame->height_px,
      1e-6 * static_cast<double>(frame_period_ns), s.station.io_core, nav::station::outcome_name(pinned.outcome));
  std::fflush(stdout);

  nav::MonotonicClock clock;
  const TimeNs start_ns = clock.now_ns();
  const TimeNs end_ns = args->device.seconds > 0.0 ? start_ns + static_cast<TimeNs>(args->device.seconds * 1e9) : -1;
  TimeNs next_pose_ns = start_ns, next_frame_ns = start_ns, next_status_ns = start_ns + kNsPerSecond;
  std::int64_t poses_written = 0, frames_written = 0, poses_back = 0;
  nav::dds::ToolPose pose;
  pose.quality = 1.0f;
  while (!nav::dds::stop_requested() && (end_ns < 0 || clock.now_ns() < end_ns)) {
    const TimeNs now_ns = clock.now_ns();
    for (; next_pose_ns <= now_ns; next_pose_ns += pose_period_ns) {
      for (std::uint32_t tool = 1; tool <= kTools; ++tool) {
        pose.tool_id = tool;
        pose.sequence_number = static_cast<std::uint64_t>(poses_written);
        pose.source_time_ns = now_ns;
        pose.position_m = {1e-3 * static_cast<double>(tool), 0.0, 0.0};
        poses_written += dds.write(pose) ? 1 : 0;
      }
    }
    for (; next_frame_ns <= now_ns; next_frame_ns += frame_period_ns) {
      frame->sequence_number = static_cast<std::uint64_t>(frames_written);
      frame->source_time_ns = now_ns;
      frames_written += dds.write(*frame) ? 1 : 0;
    }
    while (poses_read->try_pop(pose)) ++poses_back;
    while (frames_read->try_pop(*received)) pipeline.process(*received, clock);
    if (now_ns >= next_status_ns) {
      std::printf(
          "navdevice load: %.0f s, written %lld poses, %lld frames; read back %lld poses, %lld frames (filtered in "
          "%.0f ms)\n",
          1e-9 * static_cast<double>(now_ns - start_ns), static_cast<long long>(poses_written),
          static_cast<long long>(frames_written), static_cast<long long>(poses_back),
          static_cast<long long>(pipeline.frames()), pipeline.busy_ms());
      std::fflush(stdout);
      next_status_ns += kNsPerSecond;
    }
    clock.sleep_until_ns(std::min({next_pose_ns, next_frame_ns, clock.now_ns() + kPollPeriodNs}));
  }
  std::printf("navdevice load: done after %.1f s: written %lld poses, %lld frames; read back %lld poses, %lld frames\n",
              1e-9 * static_cast<double>(clock.now_ns() - start_ns), static_cast<long long>(poses_written),
              static_cast<long long>(frames_written), static_cast<long long>(poses_back),
              static_cast<long long>(pipeline.frames()));
  return 0;
}

}  // namespace navdevice
