#pragma once
// One time base for the whole library: monotonic nanoseconds. The real clock reads
// CLOCK_MONOTONIC; tests use SimulatedClock, whose time moves only when told to.
#include <atomic>
#include <cstdint>

namespace nav {

/// A timestamp or duration in nanoseconds on the monotonic clock.
using TimeNs = std::int64_t;

constexpr TimeNs kNsPerMs = 1'000'000;
constexpr TimeNs kNsPerSecond = 1'000'000'000;

/// A duration (or time) in seconds.
constexpr double seconds_of(TimeNs duration_ns) noexcept { return static_cast<double>(duration_ns) * 1e-9; }

/// The source of time for loops and timestamps; real or simulated.
class Clock {
 public:
  virtual ~Clock() = default;
  /// Current time in nanoseconds; never decreases.
  virtual TimeNs now_ns() const noexcept = 0;
  /// Returns once now_ns() >= deadline_ns (at once if already past).
  virtual void sleep_until_ns(TimeNs deadline_ns) noexcept = 0;
};

/// CLOCK_MONOTONIC, with absolute-deadline sleeps (clock_nanosleep, TIMER_ABSTIME).
class MonotonicClock final : public Clock {
 public:
  TimeNs now_ns() const noexcept override;
  void sleep_until_ns(TimeNs deadline_ns) noexcept override;
};

/// A clock for tests: starts at a given time and moves only by advance_ns() or when a
/// sleeper asks for a later deadline (it jumps there at once). Safe to read from any thread.
class SimulatedClock final : public Clock {
 public:
  explicit SimulatedClock(TimeNs start_ns = 0) : now_ns_(start_ns) {}
  TimeNs now_ns() const noexcept override { return now_ns_.load(std::memory_order_acquire); }
  void sleep_until_ns(TimeNs deadline_ns) noexcept override;
  /// Moves time forward by `duration_ns` (>= 0), as if work took that long.
  void advance_ns(TimeNs duration_ns) noexcept;

 private:
  std::atomic<TimeNs> now_ns_;
};

}  // namespace nav
