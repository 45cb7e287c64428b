#pragma once
// Plays a PLUS sequence at the recorded timing (against a Clock, so tests can use a simulated
// one) or as fast as possible: into any targets, or as an ultrasound device on DDS, each frame
// as an UltrasoundFrame and each of its valid tracked transforms as a ToolPose.
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "nav/core/clock.hpp"
#include "nav/core/error.hpp"
#include "nav/dds/dds_node.hpp"
#include "nav/dds/samples.hpp"
#include "nav/ultrasound/plus_sequence.hpp"

namespace nav::ultrasound {

/// Which recorded transform is which tool, e.g. {"ProbeToTracker", 2}.
struct ToolTrack {
  std::string transform_name;
  std::uint32_t tool_id = 0;
};

/// How a sequence is played.
struct PlayOptions {
  std::vector<ToolTrack> tools{{"ProbeToTracker", 2}};
  std::uint32_t probe_tool_id = 2;  ///< stamped on the frames
  bool as_fast_as_possible = false;
  /// Called after each frame with the number played so far; false stops the playback there
  /// (e.g. on SIGINT). Empty: play to the end.
  std::function<bool(std::size_t)> after_frame;
};

/// Frame `index` (< frames_read) as a sample stamped `source_time_ns`: pixels, spacing in
/// metres and depth (height x row spacing).
void make_frame_sample(const PlusSequence& sequence, std::size_t index, std::uint32_t probe_tool_id,
                       TimeNs source_time_ns, dds::UltrasoundFrame& out);

/// A recorded transform named "<From>To<To>" (millimetres) as a pose sample in metres with a
/// unit quaternion; frame names are the lower-case <to> and <from>.
dds::ToolPose make_pose_sample(const Matrix4Mm& matrix_mm, const std::string& transform_name, std::uint32_t tool_id,
                               std::uint64_t sequence_number, TimeNs source_time_ns);

/// What a played sequence hands on at each frame's time: each valid transform of the played
/// tracks (options.tools), then the frame's image when it was read.
struct PlayTargets {
  std::function<void(const ToolTrack& tool, const TransformTrack& track, std::size_t index, TimeNs time_ns)> transform;
  std::function<void(std::size_t index, TimeNs time_ns)> image;
};

/// Plays `sequence` into `targets` with the recorded intervals between frames (time of frame
/// 0 = clock's now), or as fast as asked. Returns the number of frames played; an error names
/// a missing track.
Result<std::size_t> play_sequence(const PlusSequence& sequence, const PlayOptions& options, Clock& clock,
                                  const PlayTargets& targets);

/// Publishes the frames read from `sequence` and their valid tool poses on `node` (which has
/// advertised both topics), played as above.
Result<std::size_t> play_sequence(dds::DdsNode& node, const PlusSequence& sequence, const PlayOptions& options,
                                  Clock& clock);

}  // namespace nav::ultrasound
