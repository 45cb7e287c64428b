#pragma once
// What every navdevice source shares: the common flags (--scene, --domain, --no-wait,
// --wait-s), the scene, the participant on the scene's domain, topic names and network (which
// also reads the station's health), waiting for a running station, and errors that name the
// device.
#include <cstddef>
#include <initializer_list>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "nav/core/clock.hpp"
#include "nav/core/error.hpp"
#include "nav/dds/dds_node.hpp"
#include "nav/dds/sample_sink.hpp"
#include "nav/station/scene.hpp"

namespace navdevice {

constexpr int kExitError = 1;
constexpr int kExitUsage = 2;

/// The flags every source takes.
struct DeviceArgs {
  std::string scene_path;
  long domain_id = -1;  ///< -1: the scene's
  bool wait_for_station = true;
  double wait_s = 60.0;
  double seconds = 0.0;  ///< how long to play; 0: the source's own default (to its end, or until stopped)
};

/// Takes args[i] (and its value, moving i past it) into `out` if it is a common flag; false
/// if it is not one. Throws std::invalid_argument / std::out_of_range on a bad number.
bool take_common_flag(const std::vector<std::string>& args, std::size_t& i, DeviceArgs& out);

/// Whether the common flags make sense (a scene given, a domain in 0..232 or -1, wait and
/// seconds >= 0).
bool common_flags_valid(const DeviceArgs& args);

/// The command line of a source that takes the common flags only; nothing on a usage error.
std::optional<DeviceArgs> parse_common_flags(const std::vector<std::string>& args);

/// This host's monotonic clock less the scene's device clock offset: the clock a device of
/// the scene stamps its samples on.
class DeviceClock final : public nav::Clock {
 public:
  explicit DeviceClock(const nav::station::DeviceClockSettings& settings)
      : offset_ns_(static_cast<nav::TimeNs>(settings.offset_ms * 1e6)) {}
  nav::TimeNs now_ns() const noexcept override { return host_.now_ns() - offset_ns_; }
  void sleep_until_ns(nav::TimeNs deadline_ns) noexcept override { host_.sleep_until_ns(deadline_ns + offset_ns_); }

 private:
  nav::MonotonicClock host_;
  nav::TimeNs offset_ns_;
};

/// "handle 1 is the needle (tool 1), 2 the probe (tool 2), ...": the roles a device's
/// ids (`device_id_name`: handle, tag) are mapped to.
std::string describe_roles(const std::vector<nav::station::ToolRole>& roles, const char* device_id_name);

/// Each role's tool id and frame name (PosePublisher's tool frames).
std::map<std::uint32_t, std::string> tool_frames(const std::vector<nav::station::ToolRole>& roles);

/// Prints "navdevice DEVICE: MESSAGE" on stderr; returns kExitError.
int fail(const char* device, const std::string& message);

/// The scene of `args`, its domain replaced by --domain when given.
nav::Result<nav::station::Scene> load_device_scene(const DeviceArgs& args);

/// A device's participant and the sink of the station's health it reads (the sink outlives
/// the participant whose listener fills it).
struct DeviceNode {
  std::unique_ptr<nav::dds::RingSink<nav::dds::StationHealth, 4>> health;
  std::unique_ptr<nav::dds::DdsNode> node;
};

/// The participant `participant_name` on the scene's domain, topic names and network, reading
/// the station's health.
nav::Result<DeviceNode> open_device_node(const nav::station::Scene& scene, const char* participant_name);

/// Waits (unless --no-wait) up to --wait-s for a running station's first health sample (a
/// recorder or a display is not a station), then, within the same time, for a reader matched to
/// each topic in `writes`, and then for a health sample published after that whose station
/// readers have matched a writer of each pose and frame topic in `writes`: the station's reader
/// may match this writer a moment after this writer matched it, and a sample written in between
/// is lost. (With several devices writing one topic, the count may be another's.)
/// Returns 0 to go on, -1 if stopped by a signal, or the exit code of the failure it printed.
int wait_for_station(const DeviceNode& device, const DeviceArgs& args, const nav::station::Scene& scene,
                     const char* device_name, std::initializer_list<nav::dds::Topic> writes);

}  // namespace navdevice
