#pragma once
// Paces a loop at a fixed period on absolute deadlines (start + k * period), so that
// jitter does not accumulate. A tick that comes too late is counted, and deadlines
// already missed are skipped rather than run in a burst.
#include <cstdint>

#include "nav/core/clock.hpp"

namespace nav {

/// What one wait_next_tick() saw.
struct Tick {
  std::int64_t index = 0;    // k of the deadline start + k * period
  TimeNs deadline_ns = 0;    // when the tick was due
  TimeNs woke_ns = 0;        // when the loop actually got it
  TimeNs lateness_ns = 0;    // woke - deadline (>= 0)
  std::int64_t skipped = 0;  // whole periods passed over because the loop was late
};

/// A fixed-rate loop timer on any Clock. noexcept, no allocation: fit for the RT thread.
class FixedRateTimer {
 public:
  FixedRateTimer(Clock& clock, TimeNs period_ns, TimeNs start_ns) noexcept
      : clock_(clock), period_ns_(period_ns), start_ns_(start_ns) {}

  /// Sleeps until the next deadline and returns it. If the caller is already later than
  /// one whole period past that deadline, the missed deadlines are skipped and counted.
  Tick wait_next_tick() noexcept;

  TimeNs period_ns() const noexcept { return period_ns_; }
  /// Ticks that came more than one period late, since construction.
  std::int64_t deadline_misses() const noexcept { return deadline_misses_; }
  /// Deadlines skipped in total, since construction.
  std::int64_t skipped_ticks() const noexcept { return skipped_ticks_; }

 private:
  Clock& clock_;
  TimeNs period_ns_;
  TimeNs start_ns_;
  std::int64_t next_index_ = 0;
  std::int64_t deadline_misses_ = 0;
  std::int64_t skipped_ticks_ = 0;
};

}  // namespace nav
