#pragma once
// Why a sample was refused at the DDS boundary, and the thread-safe counters of refusals
// that the health topic publishes.
#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>
#include <string>

#include "nav/dds/samples.hpp"

namespace nav::dds {

/// The verdict on one incoming sample: accepted (none) or the reason it was dropped.
enum class SampleFault : std::uint8_t {
  none = 0,
  malformed,            // the payload does not decode: not plain CDR (XCDR1), truncated, lengths past its end
  wrong_size,           // a length field disagrees with the data, or exceeds its bound
  non_finite,           // NaN or infinity in a number
  non_unit_quaternion,  // |q| differs from 1 by more than kQuaternionNormTolerance
  time_backwards,       // source time earlier than the previous sample of the stream
  time_out_of_window,   // source time too far from the arrival time on this host's clock (ArrivalWindow)
  unknown_tool,         // a tool id the station was not configured with
  implausible_pose,     // outside the tracker's volume, or moved faster than a tool can (PoseBounds)
  buffer_full,          // valid, but the hand-off buffer had no room
};

/// The fault's name in snake case, for logs.
const char* sample_fault_name(SampleFault fault) noexcept;

/// The input's name in snake case, for logs and displays ("needle", "respiratory", ...).
const char* station_input_name(StationInput input) noexcept;

/// Each input's refusals for a summary: "needle 3, probe 0, respiratory 0, ultrasound 1".
std::string refusals_by_input(const PerInput<std::uint64_t>& refused);

/// The samples `counts` refused as invalid: every reason but a full hand-off buffer.
std::uint64_t refused_as_invalid(const BoundaryCounts& counts) noexcept;

/// The samples `counts` dropped, by reason, for a summary: "malformed 3, time_backwards 1",
/// or "none".
std::string drops_by_reason(const BoundaryCounts& counts);

/// Counts of accepted and dropped samples. Any thread may count; any thread may read.
class BoundaryCounters {
 public:
  BoundaryCounters() = default;
  /// Counters of one topic that also count into `total` (their node's, over its topics).
  explicit BoundaryCounters(BoundaryCounters& total) noexcept : total_(&total) {}

  /// Counts one sample with its verdict. Lock-free, no allocation.
  void count(SampleFault fault) noexcept {
    counts_[static_cast<std::size_t>(fault)].fetch_add(1, std::memory_order_relaxed);
    if (total_ != nullptr) total_->count(fault);
  }
  /// The counts at the time of the call.
  BoundaryCounts snapshot() const noexcept;

 private:
  static constexpr std::size_t kFaultKinds = static_cast<std::size_t>(SampleFault::buffer_full) + 1;
  std::array<std::atomic<std::uint64_t>, kFaultKinds> counts_{};
  BoundaryCounters* total_ = nullptr;
};

}  // namespace nav::dds
