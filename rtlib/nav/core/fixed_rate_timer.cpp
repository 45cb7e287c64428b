#include "nav/core/fixed_rate_timer.hpp"

namespace nav {

Tick FixedRateTimer::wait_next_tick() noexcept {
  Tick tick;
  const TimeNs now = clock_.now_ns();
  TimeNs deadline = start_ns_ + next_index_ * period_ns_;
  if (now > deadline + period_ns_) {
    tick.skipped = (now - deadline) / period_ns_;
    next_index_ += tick.skipped;
    deadline = start_ns_ + next_index_ * period_ns_;
    skipped_ticks_ += tick.skipped;
    ++deadline_misses_;
  }
  clock_.sleep_until_ns(deadline);
  tick.index = next_index_++;
  tick.deadline_ns = deadline;
  tick.woke_ns = clock_.now_ns();
  tick.lateness_ns = tick.woke_ns - deadline;
  return tick;
}

}  // namespace nav
