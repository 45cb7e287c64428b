#pragma once
// A simulated world's devices on DDS: plays the world's recording on a participant as a
// tracker and a scanner would publish it (the needle, probe and respiratory markers on
// nav/tool_pose by tool id, the B-mode frames on nav/ultrasound_frame, each when its delivery
// time comes) and, when asked, the world's truth (tumour and needle tip, model frame) on
// nav/ground_truth at every tissue step. Every stamp is on the devices' clock: world time +
// world_to_device_ns. Used by the in-process devices of a session (station_dds.cpp) and by the
// simulated patient's own process (navdevice sim). I/O-thread code: it allocates its frame
// once, at construction.
#include <cstdint>
#include <memory>
#include <vector>

#include "nav/core/clock.hpp"
#include "nav/dds/dds_node.hpp"
#include "nav/dds/samples.hpp"
#include "nav/station/simulated_world.hpp"

namespace nav::station {

/// What a WorldPlayer has written, and lost while its participant was gone.
struct PlayerCounts {
  std::int64_t poses_written = 0, frames_written = 0, truths_written = 0;
  std::uint64_t samples_lost = 0;  ///< samples due while there was no participant
};

/// A simulated tracker's tools and where it sees the patient: the world's model-frame poses go
/// out in the tracker's frame (tracker_from_model applied), and the reference tool, when the scene
/// tracks one, at its fixed place tracker_from_reference with every respiratory sample.
struct SimulatedTracker {
  ToolIds tools;
  RigidPose tracker_from_model;      ///< tracker_from_model = tracker_from_reference * reference_from_model
  RigidPose tracker_from_reference;  ///< where the tracker sees the reference marker
};

/// A simulated tracker of `tools` seeing the reference marker at `tracker_from_reference` (when
/// `tools` has a reference; else at its origin) and the model on it by the URDF's `reference_from_model`.
SimulatedTracker simulated_tracker(const ToolIds& tools, const RigidPose& tracker_from_reference,
                                   const RigidPose& reference_from_model);

/// Plays one world's recording, in order: once, or on and on by repeating its last period.
class WorldPlayer {
 public:
  /// Plays `world` as `tracker` sees it, and its truth when `publish_truth`.
  WorldPlayer(const SimulatedWorld& world, bool publish_truth, const SimulatedTracker& tracker);

  /// Sets where world time 0 is on the devices' clock (before the first play_until).
  void set_world_to_device_ns(TimeNs world_to_device_ns) noexcept { world_to_device_ns_ = world_to_device_ns; }

  /// Plays on past the recording's end for ever by repeating its last `period_ns` (the samples
  /// measured in [duration - period, duration)), each repeat later by period_ns, with sequence
  /// numbers going on. Seamless for a world whose needle has stopped, with world_period_ns.
  void repeat_last(TimeNs period_ns);

  /// Writes on `node` what is due by world time `now_ns`; with no node (the devices are gone)
  /// the samples due are lost and counted. `clock` times each write (written_ns()).
  void play_until(TimeNs now_ns, dds::DdsNode* node, const MonotonicClock& clock);

  /// Every recorded sample has been played (the truth may go on to the world's end); never
  /// when repeating.
  bool finished() const noexcept { return repeat_period_ns_ == 0 && next_ >= world_.samples.size(); }
  const PlayerCounts& counts() const noexcept { return counts_; }
  /// When each sample of the recording's first pass was written (clock time, by sequence
  /// number = recording index when not repeating; -1: never).
  const std::vector<TimeNs>& written_ns() const noexcept { return written_ns_; }

 private:
  dds::ToolPose reference_pose(const dds::ToolPose& respiratory) const;
  /// The next sample to play and how much later than recorded it plays; null when none is left.
  const DeviceSample* next_sample(TimeNs& later_ns);
  void write(const DeviceSample& s, TimeNs later_ns, dds::DdsNode& node, const MonotonicClock& clock);
  /// The recording's time of world time `time_ns` (itself, or its place in the repeated period).
  TimeNs recording_time_ns(TimeNs time_ns) const noexcept;

  const SimulatedWorld& world_;
  bool publish_truth_;
  SimulatedTracker tracker_;
  TimeNs world_to_device_ns_ = 0;
  std::size_t next_ = 0;  ///< in the recording (first pass) or in cycle_ (repeats)
  TimeNs repeat_period_ns_ = 0;
  std::vector<std::size_t> cycle_;  ///< the repeated samples, in delivery order
  std::int64_t repeats_ = 0;        ///< 0: the first pass; k: the k-th repeat of the cycle
  std::uint64_t sequence_ = 0;
  TimeNs next_truth_ns_ = 0;
  std::unique_ptr<dds::UltrasoundFrame> frame_;
  std::vector<TimeNs> written_ns_;
  PlayerCounts counts_;
};

/// A recorded tracker sample as the ToolPose `tracker` publishes (source time: its measurement
/// time on the device's clock, world time + `world_to_device_ns`; in the tracker's frame).
dds::ToolPose tool_pose_of(const DeviceSample& sample, std::uint64_t sequence_number, TimeNs world_to_device_ns,
                           const SimulatedTracker& tracker);

}  // namespace nav::station
