#include "device_common.hpp"

#include <cstdio>

#include "nav/core/clock.hpp"
#include "nav/dds/stop_request.hpp"
#include "nav/station/station_dds.hpp"

namespace navdevice {

bool take_common_flag(const std::vector<std::string>& args, std::size_t& i, DeviceArgs& out) {
  const bool has_value = i + 1 < args.size();
  if (args[i] == "--scene" && has_value)
    out.scene_path = args[++i];
  else if (args[i] == "--domain" && has_value)
    out.domain_id = std::stol(args[++i]);
  else if (args[i] == "--wait-s" && has_value)
    out.wait_s = std::stod(args[++i]);
  else if (args[i] == "--seconds" && has_value)
    out.seconds = std::stod(args[++i]);
  else if (args[i] == "--no-wait")
    out.wait_for_station = false;
  else
    return false;
  return true;
}

bool common_flags_valid(const DeviceArgs& args) {
  return !args.scene_path.empty() && args.domain_id >= -1 && args.domain_id <= 232 && args.wait_s >= 0.0 &&
         args.seconds >= 0.0;
}

std::optional<DeviceArgs> parse_common_flags(const std::vector<std::string>& args) {
  DeviceArgs parsed;
  for (std::size_t i = 0; i < args.size(); ++i) {
    try {
      if (!take_common_flag(args, i, parsed)) return std::nullopt;
    } catch (const std::exception&) {
      return std::nullopt;
    }
  }
  return common_flags_valid(parsed) ? std::optional<DeviceArgs>(parsed) : std::nullopt;
}

std::string describe_roles(const std::vector<nav::station::ToolRole>& roles, const char* device_id_name) {
  std::string text;
  for (const nav::station::ToolRole& r : roles)
    text += (text.empty() ? std::string(device_id_name) + " " : std::string(", ")) + std::to_string(r.device_id) +
            (text.empty() ? " is" : "") + " the " + r.role + " (tool " + std::to_string(r.tool_id) + ")";
  return text;
}

std::map<std::uint32_t, std::string> tool_frames(const std::vector<nav::station::ToolRole>& roles) {
  std::map<std::uint32_t, std::string> frames;
  for (const nav::station::ToolRole& r : roles) frames[r.tool_id] = r.frame;
  return frames;
}

int fail(const char* device, const std::string& message) {
  std::fprintf(stderr, "navdevice %s: %s\n", device, message.c_str());
  return kExitError;
}

nav::Result<nav::station::Scene> load_device_scene(const DeviceArgs& args) {
  auto scene = nav::station::load_scene(args.scene_path);
  if (!scene.ok()) return scene.error();
  if (args.domain_id >= 0) scene.value().topics.domain_id = static_cast<std::uint32_t>(args.domain_id);
  return scene;
}

nav::Result<DeviceNode> open_device_node(const nav::station::Scene& scene, const char* participant_name) {
  DeviceNode device;
  device.health = std::make_unique<nav::dds::RingSink<nav::dds::StationHealth, 4>>();
  auto node =
      nav::station::make_station_node(scene.topics.domain_id, participant_name, nav::station::topic_names(scene.topics),
                                      scene.network, nav::station::Role::devices);
  if (!node.ok()) return node.error();
  device.node = std::move(node).value();
  if (const nav::Status read = device.node->subscribe(*device.health); !read.ok()) return read.error();
  return device;
}

int wait_for_station(const DeviceNode& device, const DeviceArgs& args, const nav::station::Scene& scene,
                     const char* device_name, std::initializer_list<nav::dds::Topic> writes) {
  if (!args.wait_for_station) return 0;
  std::printf("navdevice %s: waiting up to %.0f s for a running station (its health) on domain %u ...\n", device_name,
              args.wait_s, scene.topics.domain_id);
  std::fflush(stdout);
  nav::MonotonicClock clock;
  const nav::TimeNs give_up_ns = clock.now_ns() + static_cast<nav::TimeNs>(args.wait_s * 1e9);
  const auto station_reads = [&] {
    bool all = device.health->size() > 0;
    for (const nav::dds::Topic topic : writes) all = all && device.node->matched(topic) > 0;
    return all;
  };
  while (!station_reads()) {
    if (nav::dds::stop_requested()) return -1;
    if (clock.now_ns() > give_up_ns)
      return fail(device_name, device.health->size() == 0
                                   ? "no station ran on this domain within " + std::to_string(args.wait_s) + " s"
                                   : "a station runs, but reads none of this device's topics (their names differ?)");
    clock.sleep_until_ns(clock.now_ns() + 10 * nav::kNsPerMs);
  }
  nav::dds::StationHealth health;
  while (device.health->try_pop(health)) {
  }  // published before this device's writers matched
  const auto station_matched_these_writers = [&] {
    bool matched = false;
    while (device.health->try_pop(health)) {
      matched = true;
      for (const nav::dds::Topic topic : writes)
        matched = matched && (topic != nav::dds::Topic::tool_pose || health.pose_writers > 0) &&
                  (topic != nav::dds::Topic::ultrasound_frame || health.frame_writers > 0);
    }
    return matched;
  };
  while (!station_matched_these_writers()) {
    if (nav::dds::stop_requested()) return -1;
    if (clock.now_ns() > give_up_ns)
      return fail(device_name, "the station's health never said its readers matched this device's writers");
    clock.sleep_until_ns(clock.now_ns() + 10 * nav::kNsPerMs);
  }
  return 0;
}

}  // namespace navdevice
