#pragma once
// The station's DDS topics, by kind, with their names on the wire and the QoS knobs a
// deployment may turn (the QoS itself is fixed in code, in topic_qos.cpp).
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>

#include "nav/core/clock.hpp"

namespace nav::dds {

/// One topic of the station; each carries one sample type of samples.hpp.
enum class Topic : std::uint8_t {
  tool_pose,
  ultrasound_frame,
  needle_state,
  target_prediction,
  deformed_surface,
  station_health,
  ground_truth,  ///< a simulated patient's truth, for evaluation only
  needle_force,  ///< the needle's forces at the loop rate (best effort, newest only)
};

/// The number of topics (Topic values are 0 .. kTopicCount - 1).
inline constexpr std::size_t kTopicCount = static_cast<std::size_t>(Topic::needle_force) + 1;

/// The topics' names on the wire, by Topic (index static_cast<std::size_t>(topic)); an empty
/// entry keeps the default topic_name(topic). A station scene renames its topics with it.
using TopicNames = std::array<std::string, kTopicCount>;

/// The knobs of the topic QoS that a deployment or a benchmark may turn.
struct TopicQosOptions {
  /// Lets endpoints on one host exchange samples through shared buffers (no copy into a
  /// transport); off forces the transports.
  bool data_sharing = true;
  /// The longest gap between two poses of a tool before DDS reports a missed deadline.
  TimeNs pose_deadline_ns = 100 * kNsPerMs;
  /// The names the participant's topics take on the wire (empty entries: the defaults).
  TopicNames names{};
};

/// The DDS topic name, e.g. "nav/tool_pose".
const char* topic_name(Topic topic) noexcept;

/// The name `names` gives `topic`, or its default name when that entry is empty.
inline const char* topic_name(Topic topic, const TopicNames& names) noexcept {
  const std::string& name = names[static_cast<std::size_t>(topic)];
  return name.empty() ? topic_name(topic) : name.c_str();
}

}  // namespace nav::dds
