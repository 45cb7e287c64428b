#pragma once
// Recording every station topic from DDS into a recording file, and playing a recording
// back onto DDS at the recorded pace or as fast as possible. I/O-side tools: they allocate.
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <tuple>

#include "nav/core/error.hpp"
#include "nav/dds/dds_node.hpp"
#include "nav/dds/recording_file.hpp"

namespace nav::dds {

/// Samples per topic the recorder holds between two pump() calls (more are counted as
/// buffer_full drops by the node).
inline constexpr std::size_t kRecorderQueueDepth = 16;

/// Subscribes a node to every station topic and appends what arrives, with its source
/// and receive times, to a recording. Samples the boundary refuses are not recorded.
class Recorder {
 public:
  /// Subscribes `node` and creates the file at `path`. The node's listeners fill the
  /// recorder's queues: destroy the node before the recorder.
  static Result<std::unique_ptr<Recorder>> create(DdsNode& node, const std::string& path);
  /// Moves everything received so far into the file; returns the number of records written.
  Result<std::size_t> pump();
  /// Writes the index and closes the file.
  Status close() { return writer_->close(); }

 private:
  Recorder() = default;
  template <typename Sample>
  Result<std::size_t> pump_one(RingSink<Sample, kRecorderQueueDepth>& sink);

  std::unique_ptr<RecordingWriter> writer_;
  std::vector<std::uint8_t> bytes_;
  std::tuple<std::unique_ptr<RingSink<ToolPose, kRecorderQueueDepth>>,
             std::unique_ptr<RingSink<UltrasoundFrame, kRecorderQueueDepth>>,
             std::unique_ptr<RingSink<NeedleState, kRecorderQueueDepth>>,
             std::unique_ptr<RingSink<TargetPrediction, kRecorderQueueDepth>>,
             std::unique_ptr<RingSink<DeformedSurface, kRecorderQueueDepth>>,
             std::unique_ptr<RingSink<StationHealth, kRecorderQueueDepth>>,
             std::unique_ptr<RingSink<GroundTruth, kRecorderQueueDepth>>,
             std::unique_ptr<RingSink<NeedleForce, kRecorderQueueDepth>>>
      sinks_;
};

/// How fast a recording plays: with the recorded gaps between receive times, or back to back.
enum class ReplayPace { recorded, as_fast_as_possible };

/// What a replay did: records published, and the first damaged record met (with offset).
struct ReplayReport {
  std::size_t published = 0;
  std::size_t skipped = 0;  // damaged or undecodable records
  std::optional<Error> first_damage;
  bool acknowledged = false;  // every reliable sample acknowledged by its readers at the end
};

/// Publishes every intact record of `recording` on `node`. Each topic is advertised at its
/// first record, which waits up to `wait_for_readers_ns` for a reader (the pace resumes
/// after). Damaged records are skipped and the first is reported. Returns once the reliable
/// samples are acknowledged (or a few seconds passed), so that closing the node loses none.
ReplayReport replay(RecordingReader& recording, DdsNode& node, ReplayPace pace, TimeNs wait_for_readers_ns);

}  // namespace nav::dds
