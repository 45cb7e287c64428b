#pragma once
// Scripted tool motion for the simulated devices: a circle in a horizontal plane at a
// constant angular rate, with the tool rocking about its own x axis. Deterministic in time.
#include <array>

#include "nav/core/clock.hpp"

namespace nav::trackers {

/// A tool's scripted motion, tracker_from_tool(t).
struct Trajectory {
  std::array<double, 3> centre_m{0.0, 0.0, -1.0};
  double radius_m = 0.05;
  double angular_rate_rad_s = 1.0;
  double rock_amplitude_rad = 0.3;
  double rock_rate_rad_s = 2.0;

  /// Position (metres) and orientation (unit quaternion w x y z) at `time_ns`.
  void at(TimeNs time_ns, std::array<double, 3>& position_m, std::array<double, 4>& orientation_wxyz) const noexcept;
};

}  // namespace nav::trackers
