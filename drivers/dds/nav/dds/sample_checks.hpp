#pragma once
// Value checks applied to every incoming sample before it reaches the core: finite
// numbers, unit quaternions, consistent sizes, time that does not run backwards.
// Pure functions, no allocation; the listeners count what they reject.
#include "nav/core/clock.hpp"
#include "nav/dds/sample_fault.hpp"
#include "nav/dds/samples.hpp"

namespace nav::dds {

/// Largest accepted | |q| - 1 | of a pose's orientation quaternion.
inline constexpr double kQuaternionNormTolerance = 1e-3;

SampleFault check_sample(const ToolPose& pose) noexcept;
/// Also refuses an empty image, one above kMaxFramePixels and non-positive spacing or depth.
SampleFault check_sample(const UltrasoundFrame& frame) noexcept;
SampleFault check_sample(const NeedleState& needle) noexcept;
SampleFault check_sample(const TargetPrediction& prediction) noexcept;
SampleFault check_sample(const DeformedSurface& surface) noexcept;
/// Health carries only counters and flags: nothing to refuse.
SampleFault check_sample(const StationHealth& health) noexcept;
SampleFault check_sample(const GroundTruth& truth) noexcept;
SampleFault check_sample(const NeedleForce& force) noexcept;

/// How far a sample's source time may lie from its arrival. The source time, moved onto this
/// host's monotonic clock by `source_clock_offset_ns`, must fall within [arrival -
/// max_behind_ns, arrival + max_ahead_ns]: a stamp outside is refused before it can become
/// the time reference of its stream (one sample stamped far ahead would otherwise make every
/// later one "backwards").
struct ArrivalWindow {
  TimeNs source_clock_offset_ns = 0;        ///< added to a source time to put it on this host's monotonic clock
  TimeNs max_ahead_ns = 50 * kNsPerMs;      ///< clock offsets are never known exactly
  TimeNs max_behind_ns = 1 * kNsPerSecond;  ///< the slowest device's latency, with room

  /// none, or time_out_of_window (also when the arithmetic would overflow).
  SampleFault check(TimeNs source_time_ns, TimeNs arrival_ns) const noexcept {
    TimeNs on_host_ns = 0, ahead_ns = 0;
    if (__builtin_add_overflow(source_time_ns, source_clock_offset_ns, &on_host_ns) ||
        __builtin_sub_overflow(on_host_ns, arrival_ns, &ahead_ns))
      return SampleFault::time_out_of_window;
    return ahead_ns > max_ahead_ns || ahead_ns < -max_behind_ns ? SampleFault::time_out_of_window : SampleFault::none;
  }
};

/// Where and how fast a tracked tool can be: within `volume_radius_m` of the tracker's origin,
/// and, between two poses of one tool, no further apart than `max_speed_m_per_s` times the time
/// between their stamps plus `jitter_m` of measurement noise. A pose outside is refused
/// (implausible_pose) and the tool keeps its last plausible pose as the reference; the
/// distance allowed grows with the time since, so a tool seen again elsewhere is taken.
struct PoseBounds {
  double volume_radius_m = 3.0;
  double max_speed_m_per_s = 2.0;
  double jitter_m = 0.002;

  /// none or implausible_pose for `pose`, the tool's last accepted pose being `previous`
  /// (null for its first). A stamp before previous's is left to the time-order check.
  SampleFault check(const ToolPose& pose, const ToolPose* previous) const noexcept;
};

/// The time order of one stream: refuses a source time earlier than the last accepted one
/// (equal times pass). One writer thread.
class StreamOrder {
 public:
  /// none (and remembers `source_time_ns`) or time_backwards.
  SampleFault advance(TimeNs source_time_ns) noexcept {
    if (seen_ && source_time_ns < last_source_time_ns_) return SampleFault::time_backwards;
    seen_ = true;
    last_source_time_ns_ = source_time_ns;
    return SampleFault::none;
  }

 private:
  bool seen_ = false;
  TimeNs last_source_time_ns_ = 0;
};

}  // namespace nav::dds
