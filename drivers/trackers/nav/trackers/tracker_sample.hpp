#pragma once
// What every tracker driver produces before publishing: one tool's pose at the device's
// measurement time, with its tracking state. Plain data, no DDS type.
#include <array>
#include <cstdint>

#include "nav/core/clock.hpp"

namespace nav::trackers {

/// A tool's tracking state as the device reports it.
enum class ToolState : std::uint8_t {
  ok,                    // seen, fully inside the measurement volume
  partly_out_of_volume,  // seen, some markers outside the volume (pose less reliable)
  out_of_volume,         // seen, outside the characterised volume
  missing,               // not seen this frame (no pose)
  disabled,              // port handle not enabled
};

/// One tool's pose tracker_from_tool at the device's measurement time.
struct TrackerSample {
  std::uint32_t tool_id = 0;
  TimeNs measured_time_ns = 0;  // when the device measured it (on the station clock)
  ToolState state = ToolState::missing;
  std::array<double, 3> position_m{};
  std::array<double, 4> orientation_wxyz{1.0, 0.0, 0.0, 0.0};
  double rms_error_m = 0.0;  // the device's fit error, 0 when unknown
  std::uint32_t frame_number = 0;
};

/// True when the sample carries a pose (ok, partly out of or out of volume).
constexpr bool has_pose(ToolState state) noexcept {
  return state == ToolState::ok || state == ToolState::partly_out_of_volume || state == ToolState::out_of_volume;
}

}  // namespace nav::trackers
