#pragma once
// The station's DDS topics, by kind, with their names on the wire and the QoS knobs a
// deployment may turn (the QoS itself is fixed in code, in topic_qos.cpp).
#include <cstddef>
#include <cstdint>

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
};

/// The number of topics (Topic values are 0 .. kTopicCount - 1).
inline constexpr std::size_t kTopicCount = static_cast<std::size_t>(Topic::station_health) + 1;

/// The knobs of the topic QoS that a deployment or a benchmark may turn.
struct TopicQosOptions {
  /// Lets endpoints on one host exchange samples through shared buffers (no copy into a
  /// transport); off forces the transports.
  bool data_sharing = true;
  /// The longest gap between two poses of a tool before DDS reports a missed deadline.
  TimeNs pose_deadline_ns = 100 * kNsPerMs;
};

/// The DDS topic name, e.g. "nav/tool_pose".
const char* topic_name(Topic topic) noexcept;

}  // namespace nav::dds
