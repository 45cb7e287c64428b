#include "nav/dds/sample_fault.hpp"

#include <array>
#include <utility>

namespace nav::dds {

const char* sample_fault_name(SampleFault fault) noexcept {
  switch (fault) {
    case SampleFault::none:
      return "none";
    case SampleFault::malformed:
      return "malformed";
    case SampleFault::wrong_size:
      return "wrong_size";
    case SampleFault::non_finite:
      return "non_finite";
    case SampleFault::non_unit_quaternion:
      return "non_unit_quaternion";
    case SampleFault::time_backwards:
      return "time_backwards";
    case SampleFault::time_out_of_window:
      return "time_out_of_window";
    case SampleFault::unknown_tool:
      return "unknown_tool";
    case SampleFault::implausible_pose:
      return "implausible_pose";
    case SampleFault::buffer_full:
      return "buffer_full";
  }
  return "unknown";
}

const char* station_input_name(StationInput input) noexcept {
  switch (input) {
    case StationInput::needle:
      return "needle";
    case StationInput::probe:
      return "probe";
    case StationInput::respiratory:
      return "respiratory";
    case StationInput::ultrasound:
      return "ultrasound";
  }
  return "unknown";
}

namespace {

/// Every drop count of `counts` with its cause, in the order summaries list them.
std::array<std::pair<SampleFault, std::uint64_t>, 9> drops_of(const BoundaryCounts& counts) noexcept {
  return {{{SampleFault::malformed, counts.malformed},
           {SampleFault::wrong_size, counts.wrong_size},
           {SampleFault::non_finite, counts.non_finite},
           {SampleFault::non_unit_quaternion, counts.non_unit_quaternion},
           {SampleFault::time_backwards, counts.time_backwards},
           {SampleFault::time_out_of_window, counts.time_out_of_window},
           {SampleFault::unknown_tool, counts.unknown_tool},
           {SampleFault::implausible_pose, counts.implausible_pose},
           {SampleFault::buffer_full, counts.buffer_full}}};
}

}  // namespace

std::uint64_t refused_as_invalid(const BoundaryCounts& counts) noexcept {
  std::uint64_t refused = 0;
  for (const auto& [fault, count] : drops_of(counts))
    if (fault != SampleFault::buffer_full) refused += count;
  return refused;
}

std::string refusals_by_input(const PerInput<std::uint64_t>& refused) {
  std::string text;
  for (std::size_t i = 0; i < kStationInputCount; ++i)
    text += std::string(i == 0 ? "" : ", ") + station_input_name(static_cast<StationInput>(i)) + " " +
            std::to_string(refused[i]);
  return text;
}

std::string drops_by_reason(const BoundaryCounts& counts) {
  std::string text;
  for (const auto& [fault, count] : drops_of(counts)) {
    if (count == 0) continue;
    if (!text.empty()) text += ", ";
    text += std::string(sample_fault_name(fault)) + " " + std::to_string(count);
  }
  return text.empty() ? "none" : text;
}

BoundaryCounts BoundaryCounters::snapshot() const noexcept {
  const auto read = [this](SampleFault fault) {
    return counts_[static_cast<std::size_t>(fault)].load(std::memory_order_relaxed);
  };
  BoundaryCounts counts;
  counts.accepted = read(SampleFault::none);
  counts.malformed = read(SampleFault::malformed);
  counts.wrong_size = read(SampleFault::wrong_size);
  counts.non_finite = read(SampleFault::non_finite);
  counts.non_unit_quaternion = read(SampleFault::non_unit_quaternion);
  counts.time_backwards = read(SampleFault::time_backwards);
  counts.time_out_of_window = read(SampleFault::time_out_of_window);
  counts.unknown_tool = read(SampleFault::unknown_tool);
  counts.implausible_pose = read(SampleFault::implausible_pose);
  counts.buffer_full = read(SampleFault::buffer_full);
  return counts;
}

}  // namespace nav::dds
