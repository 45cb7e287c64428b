#pragma once
// The checks a decoded sample meets at the station's boundary, in order: its own content
// (check_sample), its stamp against its arrival on this host's clock (ArrivalWindow, when
// given) and its stream's time order (StreamOrder; poses are ordered per tool by their sink,
// PoseInbox). The DDS listeners and a replay of a recording apply the same ones. One thread.
#include <optional>
#include <type_traits>

#include "nav/core/clock.hpp"
#include "nav/dds/sample_checks.hpp"
#include "nav/dds/sample_fault.hpp"

namespace nav::dds {

/// One stream's boundary: what is refused and why, before its sink sees a sample.
template <typename Sample>
class SampleBoundary {
 public:
  explicit SampleBoundary(std::optional<ArrivalWindow> window = std::nullopt) noexcept : window_(window) {}

  /// none, or the first fault of `sample` arrived at `arrival_ns` (host monotonic clock).
  SampleFault admit(const Sample& sample, TimeNs arrival_ns) noexcept {
    SampleFault fault = check_sample(sample);
    if (fault == SampleFault::none && window_) fault = window_->check(sample.source_time_ns, arrival_ns);
    if constexpr (!std::is_same_v<Sample, ToolPose>) {
      if (fault == SampleFault::none) fault = order_.advance(sample.source_time_ns);
    }
    return fault;
  }

 private:
  std::optional<ArrivalWindow> window_;
  StreamOrder order_;
};

}  // namespace nav::dds
