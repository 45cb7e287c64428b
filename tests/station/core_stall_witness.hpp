#pragma once
// A test instrument that tells the host's stalls of a core from the code that runs on it
// (header-only: for the running-station tests). A thread pinned to the core at a SCHED_FIFO
// priority above the real-time loop's wakes every period on absolute deadlines and records
// how late it woke. Nothing of the station can delay it (the loop on that core runs below
// it, the other threads elsewhere), so a late wake-up is the host's: a virtual machine's core
// descheduled by its hypervisor, the kernel. A timing test then judges the loop by the
// deadlines the host left it, and prints what the host took.
#include <algorithm>
#include <atomic>
#include <cstdint>
#include <thread>
#include <vector>

#include "nav/core/clock.hpp"
#include "nav/core/fixed_rate_timer.hpp"
#include "nav/station/realtime_thread.hpp"

namespace nav::testing {

/// What a CoreStallWitness saw: its wake-ups later than half a period, each a stall of the core.
struct CoreStalls {
  bool witnessed = false;  ///< pinned and at SCHED_FIFO (else it proves nothing)
  std::int64_t wakes = 0;
  std::vector<TimeNs> stalls_ns;  ///< the lateness of each late wake-up
  TimeNs stalled_ns() const {
    TimeNs sum = 0;
    for (TimeNs s : stalls_ns) sum += s;
    return sum;
  }
  TimeNs longest_ns() const { return stalls_ns.empty() ? 0 : *std::max_element(stalls_ns.begin(), stalls_ns.end()); }
  std::int64_t longer_than(TimeNs ns) const {
    return std::count_if(stalls_ns.begin(), stalls_ns.end(), [ns](TimeNs s) { return s > ns; });
  }
};

/// Watches one core from construction to stop().
class CoreStallWitness {
 public:
  CoreStallWitness(int core, int priority, TimeNs period_ns = kNsPerMs) : period_ns_(period_ns) {
    stalls_.stalls_ns.reserve(kCapacity);
    thread_ = std::thread([this, core, priority] { run({core, priority, false}); });
    while (!started_.load(std::memory_order_acquire)) std::this_thread::yield();
  }
  CoreStallWitness(const CoreStallWitness&) = delete;
  CoreStallWitness& operator=(const CoreStallWitness&) = delete;
  ~CoreStallWitness() { stop(); }

  /// Stops the thread (within a period) and returns what it saw.
  CoreStalls stop() {
    stop_.store(true, std::memory_order_release);
    if (thread_.joinable()) thread_.join();
    return stalls_;
  }

 private:
  static constexpr std::size_t kCapacity = 1 << 16;

  void run(const station::RealtimePlan& plan) {
    const std::vector<station::SetupStep> setup = station::apply_realtime_setup(plan);
    stalls_.witnessed = std::all_of(setup.begin(), setup.end(), [](const station::SetupStep& s) {
      return s.outcome == station::SetupOutcome::applied;
    });
    MonotonicClock clock;
    FixedRateTimer timer(clock, period_ns_, clock.now_ns() + period_ns_);
    started_.store(true, std::memory_order_release);
    while (!stop_.load(std::memory_order_acquire)) {
      const Tick tick = timer.wait_next_tick();
      ++stalls_.wakes;
      const TimeNs late_ns = tick.lateness_ns + tick.skipped * period_ns_;
      if (late_ns > period_ns_ / 2 && stalls_.stalls_ns.size() < kCapacity) stalls_.stalls_ns.push_back(late_ns);
    }
  }

  TimeNs period_ns_;
  CoreStalls stalls_;
  std::atomic<bool> started_{false}, stop_{false};
  std::thread thread_;
};

}  // namespace nav::testing
