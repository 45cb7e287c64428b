#include "nav/igtl/wall_clock.hpp"

#include <time.h>

namespace nav::igtl {

TimeNs wall_now_ns() noexcept {
  timespec now{};
  clock_gettime(CLOCK_REALTIME, &now);
  return static_cast<TimeNs>(now.tv_sec) * kNsPerSecond + now.tv_nsec;
}

}  // namespace nav::igtl
