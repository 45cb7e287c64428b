#include "nav/trackers/trajectory.hpp"

#include <cmath>

namespace nav::trackers {

void Trajectory::at(TimeNs time_ns, std::array<double, 3>& position_m,
                    std::array<double, 4>& orientation_wxyz) const noexcept {
  const double t_s = static_cast<double>(time_ns) * 1e-9;
  const double heading = angular_rate_rad_s * t_s;
  position_m = {centre_m[0] + radius_m * std::cos(heading), centre_m[1] + radius_m * std::sin(heading), centre_m[2]};
  // q = q_z(heading) * q_x(rock): yaw along the circle, then the rocking tilt.
  const double rock = rock_amplitude_rad * std::sin(rock_rate_rad_s * t_s);
  const double cz = std::cos(0.5 * heading), sz = std::sin(0.5 * heading);
  const double cx = std::cos(0.5 * rock), sx = std::sin(0.5 * rock);
  orientation_wxyz = {cz * cx, cz * sx, sz * sx, sz * cx};
}

}  // namespace nav::trackers
