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
