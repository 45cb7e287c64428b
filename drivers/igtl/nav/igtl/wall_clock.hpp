#pragma once
// OpenIGTLink stamps are wall-clock time (PLUS stamps in UTC, Slicer reads UTC); the station
// stamps on its devices' clock (this host's monotonic clock less the scene's offset). A stamp
// crosses between them by keeping its age: its age on one clock, taken from the other's now.
#include "nav/core/clock.hpp"

namespace nav::igtl {

/// This host's wall clock (CLOCK_REALTIME), in ns since 1970.
TimeNs wall_now_ns() noexcept;

/// The device-clock stamp of a message stamped `wall_stamp_ns` that is seen at `wall_now_ns`
/// and `device_now_ns`; a message without a stamp (0) is stamped when seen.
inline TimeNs device_stamp_ns(TimeNs wall_stamp_ns, TimeNs wall_now_ns, TimeNs device_now_ns) noexcept {
  return wall_stamp_ns == 0 ? device_now_ns : device_now_ns - (wall_now_ns - wall_stamp_ns);
}

/// The wall-clock stamp of a sample stamped `device_stamp` on the device clock, seen at those nows.
inline TimeNs wall_stamp_ns(TimeNs device_stamp, TimeNs wall_now_ns, TimeNs device_now_ns) noexcept {
  return wall_now_ns - (device_now_ns - device_stamp);
}

}  // namespace nav::igtl
