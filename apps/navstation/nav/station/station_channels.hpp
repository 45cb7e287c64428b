#pragma once
// Internal to the running station: what its real-time and I/O threads share (the sample
// ring, the outputs' triple buffer, the clock and the start time, the outbox of DDS outputs)
// and the I/O threads (direct hand-off in station_run.cpp, DDS in station_dds.cpp).
#include <atomic>
#include <cstddef>

#include "nav/core/clock.hpp"
#include "nav/core/spsc_ring.hpp"
#include "nav/core/triple_buffer.hpp"
#include "nav/dds/station_outbox.hpp"
#include "nav/loop/operating_loop.hpp"
#include "nav/station/simulated_world.hpp"
#include "nav/station/station_run.hpp"

namespace nav::station {

inline constexpr std::size_t kRingCapacity = 1024;    // samples in flight from the I/O thread
inline constexpr TimeNs kIoPeriodNs = kNsPerMs / 10;  // the I/O thread's polling period

/// What the two threads share.
struct StationChannels {
  SpscRing<DeviceSample, kRingCapacity> samples;
  TripleBuffer<OperatingLoopOutputs> outputs;
  dds::StationOutbox* outbox = nullptr;  ///< with DDS: the real-time thread's outputs for the I/O thread to publish
  MonotonicClock clock;
  TimeNs start_ns = 0;  ///< written by the real-time thread before `started`
  std::atomic<bool> started{false};
  std::atomic<bool> realtime_done{false};

  /// Run time (since the first tick's deadline) now.
  TimeNs run_time_ns() const noexcept { return clock.now_ns() - start_ns; }
  /// I/O side: waits until the real-time thread has set the start time.
  void wait_for_start() noexcept {
    while (!started.load(std::memory_order_acquire)) clock.sleep_until_ns(clock.now_ns() + kIoPeriodNs);
  }
};

/// Pins the calling I/O thread to its core and asks its SCHED_FIFO priority, when one is set
/// (above the devices and displays beside it on that core, below the real-time thread).
void setup_io_thread(const StationRunOptions& options, StationRun& run);

struct StationDdsLink;

/// The I/O thread on DDS: the station's participant takes the devices' poses and frames, finds
/// the tumour in the frames (through `imaging`'s probe calibration, each frame on its own grid)
/// and feeds the ring; an output thread beside it publishes the outbox and the surface; with a
/// `world`, the in-process devices' participant plays its recording (station_dds.cpp),
/// without, the devices are other processes.
void dds_io_thread(const OperatingLoopModel& loop, const SimulatedWorld* world, const ProbeImaging& imaging,
                   StationChannels& ch, StationRun& run, const StationRunOptions& options, StationDdsLink& link);

/// How the real-time thread stamps the outputs it hands to DDS.
struct OutputStamps {
  TimeNs loop_to_host_ns = 0;     ///< loop time + this: the host's monotonic clock
  TimeNs display_latency_ns = 0;  ///< the horizon of the predictions ahead
  std::uint32_t needle_tool_id = 1;
};

/// Real-time side, with DDS: pushes the tick's outputs into the outbox (predictions and the
/// needle at each liver step, health every health_every_ticks ticks), stamped on the host's
/// clock. The needle is the needle model's centreline with its tip force when the loop steps
/// one, its tip otherwise. No allocation, never blocks.
void push_outputs(dds::StationOutbox& outbox, const OperatingLoopOutputs& outputs, const OutputStamps& stamps,
                  std::int64_t health_every_ticks, std::uint64_t deadline_misses, TimeNs step_max_ns) noexcept;

}  // namespace nav::station
