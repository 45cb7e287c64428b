#include "nav/trackers/pose_publisher.hpp"

#include <algorithm>

namespace nav::trackers {
namespace {

float quality_of(ToolState state) {
  switch (state) {
    case ToolState::ok:
      return 1.0f;
    case ToolState::partly_out_of_volume:
      return 0.5f;
    case ToolState::out_of_volume:
      return 0.25f;
    default:
      return 0.0f;
  }
}

}  // namespace

dds::ToolPose to_tool_pose(const TrackerSample& sample, std::uint64_t sequence_number, const std::string& frame_to,
                           const std::string& frame_from) {
  dds::ToolPose pose;
  pose.tool_id = sample.tool_id;
  pose.sequence_number = sequence_number;
  pose.source_time_ns = sample.measured_time_ns;
  pose.position_m = sample.position_m;
  pose.orientation_wxyz = sample.orientation_wxyz;
  const double variance_m2 = sample.rms_error_m * sample.rms_error_m;
  pose.position_covariance_m2 = {variance_m2, 0.0, 0.0, 0.0, variance_m2, 0.0, 0.0, 0.0, variance_m2};
  pose.quality = quality_of(sample.state);
  dds::set_frame_name(pose.frame_to, frame_to);
  dds::set_frame_name(pose.frame_from, frame_from);
  return pose;
}

Result<PosePublisher> PosePublisher::create(dds::DdsNode& node, std::string tracker_frame,
                                            std::map<std::uint32_t, std::string> tool_frames) {
  if (Status advertised = node.advertise<dds::ToolPose>(); !advertised) return advertised.error();
  return PosePublisher(node, std::move(tracker_frame), std::move(tool_frames));
}

bool PosePublisher::publish(const TrackerSample& sample) {
  if (!has_pose(sample.state)) {
    ++counts_.without_pose;
    return false;
  }
  const auto frame = tool_frames_.find(sample.tool_id);
  const std::string tool_frame = frame != tool_frames_.end() ? frame->second : "tool_" + std::to_string(sample.tool_id);
  const dds::ToolPose pose = to_tool_pose(sample, sequence_numbers_[sample.tool_id]++, tracker_frame_, tool_frame);
  if (!node_->write(pose)) {
    ++counts_.refused;
    return false;
  }
  ++counts_.published;
  return true;
}

}  // namespace nav::trackers
