#pragma once
// Publishes tracker samples as the station's ToolPose samples on DDS (tracker_from_tool, frame
// names from the tool table); samples without a pose (missing, disabled) are counted, not
// published. I/O-thread code.
#include <cstdint>
#include <map>
#include <string>

#include "nav/dds/dds_node.hpp"
#include "nav/trackers/tracker_sample.hpp"

namespace nav::trackers {

/// How many samples a publisher sent and why it held others back.
struct PublishCounts {
  std::uint64_t published = 0;
  std::uint64_t without_pose = 0;  // missing or disabled tools
  std::uint64_t refused = 0;       // DDS refused the write
};

/// Turns tracker samples into ToolPose samples and writes them on one node.
class PosePublisher {
 public:
  /// Advertises the pose topic on `node` (which must outlive the publisher). `tool_frames`
  /// names each tool's frame (e.g. 1 -> "needle_marker"); the parent frame is `tracker_frame`.
  static Result<PosePublisher> create(dds::DdsNode& node, std::string tracker_frame,
                                      std::map<std::uint32_t, std::string> tool_frames);
  /// Publishes `sample` if it carries a pose; true when written.
  bool publish(const TrackerSample& sample);
  const PublishCounts& counts() const noexcept { return counts_; }

 private:
  PosePublisher(dds::DdsNode& node, std::string tracker_frame, std::map<std::uint32_t, std::string> tool_frames)
      : node_(&node), tracker_frame_(std::move(tracker_frame)), tool_frames_(std::move(tool_frames)) {}
  dds::DdsNode* node_;
  std::string tracker_frame_;
  std::map<std::uint32_t, std::string> tool_frames_;
  std::map<std::uint32_t, std::uint64_t> sequence_numbers_;
  PublishCounts counts_;
};

/// The ToolPose of a sample (quality: 1 ok, 0.5 partly out of volume, 0.25 out of volume).
dds::ToolPose to_tool_pose(const TrackerSample& sample, std::uint64_t sequence_number, const std::string& frame_to,
                           const std::string& frame_from);

}  // namespace nav::trackers
