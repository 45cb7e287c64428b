#include "nav/core/clock.hpp"

#include <cerrno>
#include <ctime>

namespace nav {

TimeNs MonotonicClock::now_ns() const noexcept {
  timespec now{};
  clock_gettime(CLOCK_MONOTONIC, &now);
  return static_cast<TimeNs>(now.tv_sec) * kNsPerSecond + now.tv_nsec;
}

void MonotonicClock::sleep_until_ns(TimeNs deadline_ns) noexcept {
  timespec deadline{};
  deadline.tv_sec = static_cast<time_t>(deadline_ns / kNsPerSecond);
  deadline.tv_nsec = static_cast<long>(deadline_ns % kNsPerSecond);
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &deadline, nullptr) == EINTR) {
  }
}

void SimulatedClock::sleep_until_ns(TimeNs deadline_ns) noexcept {
  TimeNs current = now_ns_.load(std::memory_order_acquire);
  while (current < deadline_ns && !now_ns_.compare_exchange_weak(current, deadline_ns, std::memory_order_acq_rel)) {
  }
}

void SimulatedClock::advance_ns(TimeNs duration_ns) noexcept {
  if (duration_ns > 0) now_ns_.fetch_add(duration_ns, std::memory_order_acq_rel);
}

}  // namespace nav
