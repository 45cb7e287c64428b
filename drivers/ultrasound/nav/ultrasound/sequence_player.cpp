#include "nav/ultrasound/sequence_player.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <memory>

#include "nav/ultrasound/plus_transform.hpp"

namespace nav::ultrasound {
namespace {

/// `text` in lower case, as the player names frames.
std::string lower_case(std::string text) {
  for (char& c : text) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return text;
}

}  // namespace

void make_frame_sample(const PlusSequence& sequence, std::size_t index, std::uint32_t probe_tool_id,
                       TimeNs source_time_ns, dds::UltrasoundFrame& out) {
  out.sequence_number = index;
  out.source_time_ns = source_time_ns;
  out.probe_tool_id = probe_tool_id;
  out.width_px = sequence.width_px;
  out.height_px = sequence.height_px;
  out.pixel_spacing_m = {sequence.spacing_mm[0] * 1e-3, sequence.spacing_mm[1] * 1e-3};
  out.depth_m = sequence.height_px * out.pixel_spacing_m[1];
  std::copy_n(sequence.frame(index), std::min(sequence.frame_pixels(), dds::kMaxFramePixels), out.pixels.begin());
}

dds::ToolPose make_pose_sample(const Matrix4Mm& matrix_mm, const std::string& transform_name, std::uint32_t tool_id,
                               std::uint64_t sequence_number, TimeNs source_time_ns) {
  const Eigen::Isometry3d transform = rigid_transform_m(matrix_mm);
  Eigen::Quaterniond quaternion(transform.linear());
  quaternion.normalize();
  dds::ToolPose pose;
  pose.tool_id = tool_id;
  pose.sequence_number = sequence_number;
  pose.source_time_ns = source_time_ns;
  pose.position_m = {transform.translation().x(), transform.translation().y(), transform.translation().z()};
  pose.orientation_wxyz = {quaternion.w(), quaternion.x(), quaternion.y(), quaternion.z()};
  pose.quality = 1.0f;
  const auto to = transform_name.find("To");
  dds::set_frame_name(pose.frame_from, lower_case(transform_name.substr(0, to)));
  dds::set_frame_name(pose.frame_to,
                      lower_case(to == std::string::npos ? std::string{} : transform_name.substr(to + 2)));
  return pose;
}

Result<std::size_t> play_sequence(const PlusSequence& sequence, const PlayOptions& options, Clock& clock,
                                  const PlayTargets& targets) {
  std::vector<const TransformTrack*> tracks;
  for (const ToolTrack& tool : options.tools) {
    tracks.push_back(sequence.find_transform(tool.transform_name));
    if (tracks.back() == nullptr)
      return Error{.message = "no such transform in the sequence", .file = sequence.path, .field = tool.transform_name};
  }
  const bool has_images = sequence.frame_pixels() > 0;
  const std::size_t frames = has_images ? sequence.frames_read : sequence.frame_count;
  const TimeNs start_ns = clock.now_ns();
  for (std::size_t i = 0; i < frames; ++i) {
    const auto offset_ns =
        static_cast<TimeNs>(std::llround((sequence.timestamps_s[i] - sequence.timestamps_s[0]) * 1e9));
    const TimeNs time_ns = start_ns + std::max<TimeNs>(offset_ns, 0);
    if (!options.as_fast_as_possible) clock.sleep_until_ns(time_ns);
    for (std::size_t t = 0; t < tracks.size(); ++t)
      if (tracks[t]->valid[i] != 0) targets.transform(options.tools[t], *tracks[t], i, time_ns);
    if (has_images && sequence.image_valid[i] != 0) targets.image(i, time_ns);
    if (options.after_frame && !options.after_frame(i + 1)) return i + 1;
  }
  return frames;
}

Result<std::size_t> play_sequence(dds::DdsNode& node, const PlusSequence& sequence, const PlayOptions& options,
                                  Clock& clock) {
  auto frame = std::make_unique<dds::UltrasoundFrame>();
  return play_sequence(
      sequence, options, clock,
      {.transform =
           [&](const ToolTrack& tool, const TransformTrack& track, std::size_t index, TimeNs time_ns) {
             node.write(make_pose_sample(track.matrices_mm[index], track.name, tool.tool_id, index, time_ns));
           },
       .image =
           [&](std::size_t index, TimeNs time_ns) {
             make_frame_sample(sequence, index, options.probe_tool_id, time_ns, *frame);
             node.write(*frame);
           }});
}

}  // namespace nav::ultrasound
