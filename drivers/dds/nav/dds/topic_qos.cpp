#include "nav/dds/topic_qos.hpp"

#include <cstdint>

namespace nav::dds {
namespace {

namespace fdds = eprosima::fastdds::dds;

/// Poses of every tool share one unkeyed topic and a tracker writes them in bursts (one per
/// tool at each measurement): a history of one would let each pose of a burst replace the one
/// before it before the reader takes it (a third of the demo's poses were lost so, and the
/// needle went stale). This holds a burst of kPoseBurstTools tools with room to spare.
constexpr int kPoseBurstTools = 8;

/// The policies that writers and readers of `topic` share; Qos is either endpoint's QoS.
template <typename Qos>
Qos endpoint_qos(Topic topic, const TopicQosOptions& options) {
  Qos qos;
  qos.history().kind = fdds::KEEP_LAST_HISTORY_QOS;
  qos.history().depth = topic == Topic::tool_pose ? kPoseBurstTools : topic == Topic::ultrasound_frame ? 2 : 1;
  // A force older than the newest is of no use to a haptic loop: best effort, and newest only.
  const bool best_effort =
      topic == Topic::tool_pose || topic == Topic::ultrasound_frame || topic == Topic::needle_force;
  qos.reliability().kind = best_effort ? fdds::BEST_EFFORT_RELIABILITY_QOS : fdds::RELIABLE_RELIABILITY_QOS;
  qos.durability().kind =
      topic == Topic::station_health ? fdds::TRANSIENT_LOCAL_DURABILITY_QOS : fdds::VOLATILE_DURABILITY_QOS;
  if (topic == Topic::tool_pose) {
    qos.deadline().period =
        eprosima::fastrtps::Duration_t(static_cast<std::int32_t>(options.pose_deadline_ns / kNsPerSecond),
                                       static_cast<std::uint32_t>(options.pose_deadline_ns % kNsPerSecond));
  }
  if (options.data_sharing) {
    qos.data_sharing().automatic();
  } else {
    qos.data_sharing().off();
  }
  return qos;
}

}  // namespace

const char* topic_name(Topic topic) noexcept {
  switch (topic) {
    case Topic::tool_pose:
      return "nav/tool_pose";
    case Topic::ultrasound_frame:
      return "nav/ultrasound_frame";
    case Topic::needle_state:
      return "nav/needle_state";
    case Topic::target_prediction:
      return "nav/target_prediction";
    case Topic::deformed_surface:
      return "nav/deformed_surface";
    case Topic::station_health:
      return "nav/station_health";
    case Topic::ground_truth:
      return "nav/ground_truth";
    case Topic::needle_force:
      return "nav/needle_force";
  }
  return "nav/unknown";
}

fdds::DataWriterQos writer_qos(Topic topic, const TopicQosOptions& options) {
  return endpoint_qos<fdds::DataWriterQos>(topic, options);
}

fdds::DataReaderQos reader_qos(Topic topic, const TopicQosOptions& options) {
  return endpoint_qos<fdds::DataReaderQos>(topic, options);
}

}  // namespace nav::dds
