// navdevice apriltag: a camera (a device, a video or an image sequence, read through OpenCV's
// capture) watching tag36h11 markers as the station's tracker: each frame's tags are detected
// and their poses solved with the scene's camera intrinsics (navtool calib camera) and tag
// size; the tag the scene names for a tool (devices.tracker.tags) is that tool, or the tags of
// its rigid body (devices.tracker.bodies, solved on all their corners together), its pose in
// the camera's frame (the tracker's) stamped at the frame's grab on the scene's device clock.
// A file or a sequence is paced at devices.tracker.rate_hz; a camera at its own rate.
#include "apriltag_device.hpp"

#include <cstdio>
#include <optional>
#include <string>
#include <vector>

#include "device_common.hpp"
#include "nav/dds/stop_request.hpp"
#include "nav/trackers/apriltag_tracker.hpp"
#include "nav/trackers/camera_file.hpp"
#include "nav/trackers/gray_image.hpp"
#include "nav/trackers/pose_publisher.hpp"
#include "nav/ultrasound/capture_source.hpp"

namespace navdevice {
namespace {

using nav::TimeNs;

constexpr const char* kUsage =
    "usage: navdevice apriltag --scene FILE [--seconds S] [--domain D] [--no-wait] [--wait-s S]\n"
    "  the scene's devices.tracker (kind: apriltag): camera, tag_size_m, intrinsics, tags; --seconds 0 (default):\n"
    "  to the end of the stream or until stopped\n";

/// The scene's tools as rigid bodies: the tags of devices.tracker.bodies at their poses on the
/// tool, or a tool's one tag of devices.tracker.tags with the tool's frame at the tag.
std::vector<nav::trackers::TagBody> tool_bodies(const std::vector<nav::station::ToolRole>& roles,
                                                const nav::station::TrackerSettings& t) {
  std::vector<nav::trackers::TagBody> bodies;
  for (const nav::station::ToolRole& r : roles) {
    nav::trackers::TagBody body{r.tool_id, {}};
    const auto declared = t.tag_bodies.find(r.role);
    if (declared == t.tag_bodies.end()) {
      body.tags.push_back({static_cast<int>(r.device_id), Eigen::Isometry3d::Identity()});
    } else {
      for (const nav::station::ToolTag& tag : declared->second) {
        Eigen::Isometry3d tool_from_tag(tag.tool_from_tag.rotation);
        tool_from_tag.translation() = tag.tool_from_tag.position_m;
        body.tags.push_back({tag.id, tool_from_tag});
      }
    }
    bodies.push_back(std::move(body));
  }
  return bodies;
}

/// What the start-up line says of the tools: a body's tags, or the tool's one tag.
std::string describe_bodies(const std::vector<nav::trackers::TagBody>& bodies,
                            const std::vector<nav::station::ToolRole>& roles) {
  std::string text;
  for (std::size_t i = 0; i < roles.size(); ++i) {
    std::string tags;
    for (const nav::trackers::BodyTag& tag : bodies[i].tags) tags += (tags.empty() ? "" : "+") + std::to_string(tag.id);
    text += (text.empty() ? "" : ", ") + std::string(bodies[i].tags.size() > 1 ? "tags " : "tag ") + tags + " the " +
            roles[i].role + " (tool " + std::to_string(roles[i].tool_id) + ")";
  }
  return text;
}

}  // namespace

int run_apriltag(const std::vector<std::string>& arguments) {
  const std::optional<DeviceArgs> args = parse_common_flags(arguments);
  if (!args) {
    std::fprintf(stderr, "%s", kUsage);
    return kExitUsage;
  }
  nav::dds::install_stop_handlers();
  auto scene = load_device_scene(*args);
  if (!scene.ok()) return fail("apriltag", scene.error().describe());
  const nav::station::Scene& s = scene.value();
  const nav::station::TrackerSettings& t = s.devices.tracker;
  if (t.kind != nav::station::TrackerKind::apriltag)
    return fail("apriltag", s.source_path + ": devices.tracker is not an AprilTag tracker (kind: apriltag)");
  if (t.camera_intrinsics_path.empty())
    return fail(
        "apriltag",
        s.source_path + ": devices.tracker.intrinsics is required to track tags (navtool calib camera --out FILE)");
  auto camera = nav::trackers::read_camera_intrinsics(t.camera_intrinsics_path);
  if (!camera.ok()) return fail("apriltag", camera.error().describe());
  const std::vector<nav::station::ToolRole> roles = nav::station::tool_roles(t.tools, t.tag_ids);
  const std::vector<nav::trackers::TagBody> bodies = tool_bodies(roles, t);
  auto tracker = nav::trackers::AprilTagTracker::create(camera.value(), t.tag_size_m, bodies);
  if (!tracker.ok()) return fail("apriltag", tracker.error().describe());
  DeviceClock clock(s.devices.clock);
  auto capture = nav::ultrasound::CaptureSource::open(t.camera_device, {}, clock);
  if (!capture.ok()) return fail("apriltag", capture.error().describe());
  const bool paced = !nav::station::is_device_index(t.camera_device) && t.camera_device.rfind("/dev/", 0) != 0;
  std::printf("navdevice apriltag: %s: tags of %.1f mm, %s%s\n", t.camera_device.c_str(), 1e3 * t.tag_size_m,
              describe_bodies(bodies, roles).c_str(), paced ? "; a file, paced at rate_hz" : "");
  std::fflush(stdout);

  auto device = open_device_node(s, "navdevice_apriltag");
  if (!device.ok()) return fail("apriltag", device.error().describe());
  nav::dds::DdsNode& dds = *device.value().node;
  auto publisher = nav::trackers::PosePublisher::create(dds, "camera", tool_frames(roles));
  if (!publisher.ok()) return fail("apriltag", publisher.error().describe());
  if (const int waited = wait_for_station(device.value(), *args, s, "apriltag", {nav::dds::Topic::tool_pose});
      waited != 0)
    return waited < 0 ? 0 : waited;

  const auto period_ns = static_cast<TimeNs>(1e9 / t.rate_hz);
  const TimeNs start_ns = clock.now_ns();
  const TimeNs end_ns = args->seconds > 0.0 ? start_ns + static_cast<TimeNs>(args->seconds * 1e9) : 0;
  TimeNs next_frame_ns = start_ns, next_status_ns = start_ns + nav::kNsPerSecond;
  auto frame = std::make_unique<nav::dds::UltrasoundFrame>();
  bool ended = false;
  while (!nav::dds::stop_requested() && (end_ns == 0 || clock.now_ns() < end_ns)) {
    if (paced) clock.sleep_until_ns(next_frame_ns);
    next_frame_ns += period_ns;
    const auto grabbed = capture.value()->next(*frame);
    if (!grabbed.ok()) return fail("apriltag", grabbed.error().describe());
    if (!grabbed.value()) {
      ended = true;
      break;
    }
    for (const nav::trackers::TrackerSample& sample :
         tracker.value()->track(nav::trackers::gray_image_from_frame(*frame), frame->source_time_ns))
      publisher.value().publish(sample);
    if (clock.now_ns() >= next_status_ns) {
      const nav::trackers::PublishCounts& c = publisher.value().counts();
      std::printf(
          "navdevice apriltag: %.0f s, %llu frames, %llu poses published, %llu tool samples without a pose; stations "
          "reading: %zu\n",
          1e-9 * static_cast<double>(next_status_ns - start_ns),
          static_cast<unsigned long long>(capture.value()->frames_read()), static_cast<unsigned long long>(c.published),
          static_cast<unsigned long long>(c.without_pose), dds.matched(nav::dds::Topic::tool_pose));
      std::fflush(stdout);
      next_status_ns += nav::kNsPerSecond;
    }
  }
  dds.wait_for_acknowledgments(nav::kNsPerSecond);
  const nav::trackers::PublishCounts& c = publisher.value().counts();
  std::printf(
      "navdevice apriltag: %s after %.1f s: %llu frames, %llu poses published, %llu tool samples without a pose\n",
      ended                        ? "end of the stream"
      : nav::dds::stop_requested() ? "stopped"
                                   : "done",
      1e-9 * static_cast<double>(clock.now_ns() - start_ns),
      static_cast<unsigned long long>(capture.value()->frames_read()), static_cast<unsigned long long>(c.published),
      static_cast<unsigned long long>(c.without_pose));
  return 0;
}

}  // namespace navdevice
