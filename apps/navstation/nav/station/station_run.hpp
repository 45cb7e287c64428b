#pragma once
// The running station on a simulated world. run_station() runs two threads: the real-time
// thread (pinned and prioritised as the scene asks, paced by a FixedRateTimer on the
// MonotonicClock at the loop rate) drains the samples that reach it through a lock-free ring
// into the OperatingLoop, ticks it, publishes its outputs through a triple buffer (and, with
// DDS, into the StationOutbox) and records its step times, lateness and predictions into
// preallocated arrays; the I/O thread takes the devices' samples (directly from the world's
// recording, each when its delivery time comes, or from DDS: station_dds.hpp), finds the
// tumour in each ultrasound frame (TumourObserver), hands poses and tumour points to the
// real-time thread and reads the published outputs as a display would. replay_station()
// feeds a recording to the same loop on a SimulatedClock: deterministic, bitwise repeatable,
// and the way the figures without assimilation are made (without the tumour points).
#include <atomic>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "nav/core/clock.hpp"
#include "nav/core/error.hpp"
#include "nav/dds/sample_checks.hpp"
#include "nav/dds/samples.hpp"
#include "nav/dds/topics.hpp"
#include "nav/loop/operating_loop.hpp"
#include "nav/station/realtime_thread.hpp"
#include "nav/station/scene.hpp"
#include "nav/station/simulated_world.hpp"
#include "nav/station/tumour_observer.hpp"

namespace nav::station {

/// What one tick predicted (model frame, metres).
struct TickRecord {
  TimeNs time_ns = 0;         ///< the tick's time (world clock)
  TimeNs tissue_time_ns = 0;  ///< the time of the liver step behind the tumour values
  Point3 tumour_now_m{}, tumour_ahead_m{}, needle_tip_m{};
  bool degraded = true;            ///< the loop's degraded output
  bool needle_degraded = true;     ///< the needle input degraded (held, extrapolated too far or missing)
  std::uint32_t needle_flags = 0;  ///< the needle input's HealthFlag bits
  std::uint32_t health_flags = 0;  ///< every HealthFlag bit of the tick (what the station's health reports)
  double tip_force_n = 0.0;  ///< the modelled tissue force on the needle's tip (magnitude; 0 without a needle model)
  int punctures = 0;         ///< surfaces the modelled needle has punctured
};

/// Step time and timing statistics of a real-time run.
struct StepStatistics {
  std::int64_t ticks = 0;
  double median_us = 0.0, p99_us = 0.0, p999_us = 0.0, p9999_us = 0.0,
         max_us = 0.0;                                    ///< of the step (drain, tick, publish)
  double jitter_us = 0.0;                                 ///< standard deviation of the ticks' lateness
  double lateness_p99_us = 0.0, lateness_p9999_us = 0.0;  ///< of the ticks' wake-ups after their deadlines
  double max_lateness_us = 0.0;                           ///< worst wake-up after a deadline (skipped periods included)
  std::int64_t latest_tick = 0;                           ///< the tick (count from the run's start) that woke that late
  std::int64_t deadline_misses = 0;                       ///< ticks later than the miss threshold
  std::int64_t late_over_1ms = 0;                         ///< ticks more than 1 ms late (a whole period at 1 kHz)
  std::int64_t skipped_ticks = 0;                         ///< deadlines passed over because the loop was late
};

/// The statistics of step times and lateness (both microseconds, one per tick).
StepStatistics step_statistics(std::vector<double> step_us, const std::vector<double>& lateness_us,
                               double miss_threshold_us);

/// A device participant that goes away: destroyed at from_ns (run time) and created again at
/// to_ns; the samples due in between are lost with it.
struct PeerOutage {
  TimeNs from_ns = 0;
  TimeNs to_ns = 0;
};

struct DisplaySurface;

/// The devices and the station on DDS instead of the direct hand-off.
struct DdsRunOptions {
  std::uint32_t domain_id = 0;
  dds::TopicNames topic_names{};               ///< the topics' names (empty entries: the defaults)
  NetworkSettings network;                     ///< the participants' local address and peers
  ToolIds tools;                               ///< the tracked tools' ids on nav/tool_pose
  RigidPose reference_from_model;              ///< the URDF's registration (tracker_registration.hpp)
  RigidPose simulated_tracker_from_reference;  ///< where the in-process simulated tracker sees the reference
                                               ///< (world_player.hpp)
  std::optional<PeerOutage> device_outage;     ///< the devices' participant goes away once
  TimeNs health_period_ns = 100 * kNsPerMs;    ///< the station's health is published this often
  const DisplaySurface* surface = nullptr;     ///< published on nav/deformed_surface when given (outlives the run)
  TimeNs surface_period_ns = 50 * kNsPerMs;    ///< of liver time between two published surfaces
  /// How the devices' stamps map onto this host's monotonic clock, and how far from its
  /// arrival a pose or frame may be stamped (the simulated devices stamp accordingly).
  dds::ArrivalWindow arrival;
  dds::PoseBounds pose_bounds;  ///< where and how fast the tracked tools can be
  TimeNs bad_sample_hold_ns =
      2 * kNsPerSecond;  ///< a sample refused at the boundary keeps bad_sample raised on the health this long
};

/// Latency statistics in microseconds.
struct LatencyStatistics {
  std::int64_t count = 0;
  double median_us = 0.0, p99_us = 0.0, p999_us = 0.0, p9999_us = 0.0, max_us = 0.0;
};

/// How a real-time run is set up.
struct StationRunOptions {
  TimeNs duration_ns = 10 * kNsPerSecond;
  TimeNs miss_threshold_ns = 5 * kNsPerMs;  ///< a tick woken later than this after its deadline is a miss
  RealtimePlan realtime;                    ///< the real-time thread's core, priority and memory lock
  int io_core = 0;                          ///< the I/O thread's core
  int io_priority = 0;                      ///< the I/O thread's SCHED_FIFO priority (0: normal scheduling)
  std::optional<DdsRunOptions> dds;         ///< devices on DDS (station_dds.hpp); direct hand-off without
  TumourObserverOptions observer;
  const std::atomic<bool>* stop = nullptr;  ///< when set and raised (SIGINT, SIGTERM), the run ends at its next tick
};

/// What the DDS side of a run saw.
struct DdsRunReport {
  LatencyStatistics pose_latency;  ///< the devices' write to the station's listener
  LatencyStatistics frame_latency;
  std::int64_t poses_written = 0, frames_written = 0;  ///< by the devices
  std::int64_t poses_accepted = 0;                     ///< by the station's pose inbox (checked, in time order)
  std::int64_t poses_received = 0;                     ///< taken by the I/O thread: the newest of each tool per poll
  std::int64_t frames_received = 0;
  std::uint64_t poses_lost = 0,
                frames_lost = 0;       ///< sent to the station and never delivered (DDS's sample-lost status)
  std::int64_t outputs_published = 0;  ///< predictions, needle states and health samples written
  std::uint64_t outbox_dropped = 0;
  std::int64_t forces_published = 0;      ///< nav/needle_force samples written, one per tick with a needle model
  std::uint64_t forces_dropped = 0;       ///< refused by their full ring (the output thread lagged 64 ticks)
  TimeNs device_gone_ns = -1;             ///< when the devices' participant began to be destroyed (run time; -1: never)
  TimeNs device_back_ns = -1;             ///< when it began to be created again
  TimeNs peer_lost_seen_ns = -1;          ///< when the I/O thread saw no pose writer any more
  TimeNs peer_back_seen_ns = -1;          ///< when it saw one again
  std::uint64_t device_samples_lost = 0;  ///< samples due while the devices were gone
  std::int64_t surfaces_published = 0;
  std::int64_t surface_periods_passed_over = 0;  ///< periods of liver time the I/O thread read no output in (it lagged)
  LatencyStatistics surface_reconstruction;      ///< the I/O thread's time per surface
  dds::BoundaryCounts boundary;                  ///< what the station's participant accepted and refused, by reason
  dds::PerInput<std::uint64_t> input_refused{};  ///< of those refused, each input's (the rest: not a configured tool's)
  std::int64_t unregistered_poses = 0;           ///< poses before the tracked reference's first (not used)
};

/// What a real-time run measured.
struct StationRun {
  TimeNs start_ns = 0;  ///< run time 0 on this host's monotonic clock (the outputs on DDS are stamped on that clock)
  StepStatistics steps;
  std::vector<TickRecord> ticks;          ///< one per tick run
  std::vector<SetupStep> realtime_setup;  ///< what the real-time thread's setup did
  SetupStep io_pin;                       ///< the I/O thread's pinning
  SetupStep io_fifo;                      ///< the I/O thread's SCHED_FIFO, when asked
  std::int64_t resident_at_start_bytes =
      0;  ///< the process's resident memory once the loop started (its buffers locked; live runs)
  std::int64_t outputs_read = 0;        ///< new outputs the I/O thread read from the triple buffer
  std::int64_t samples_pushed = 0;      ///< samples the I/O thread handed to the real-time thread
  std::int64_t samples_after_loop = 0;  ///< samples delivered within the run that the I/O thread reached only after the
                                        ///< loop had stopped (it lagged: direct hand-off)
  ObserverCounts observer;              ///< the ultrasound frames and what became of them
  LatencyStatistics frame_processing;   ///< the observer's time per frame (tumour tracker)
  std::optional<DdsRunReport> dds;
};

/// Every HealthFlag bit of a tick's outputs: the tissue's, the inputs' and the loop's.
std::uint32_t health_flag_bits(const OperatingLoopOutputs& outputs) noexcept;

/// Runs the station in real time on `world`'s recording for options.duration_ns.
Result<StationRun> run_station(const OperatingLoopModel& loop, const SimulatedWorld& world,
                               const StationRunOptions& options);

/// Runs the station in real time for options.duration_ns on devices that are other processes
/// (options.dds is required): the tumour is found in their frames through `imaging`'s probe
/// calibration.
Result<StationRun> run_live_station(const OperatingLoopModel& loop, const ProbeImaging& imaging,
                                    const StationRunOptions& options);

/// An 8-bit row-major frame on its own grid, as the observer reads it.
struct FrameView {
  const std::uint8_t* pixels = nullptr;
  std::uint32_t width_px = 0, height_px = 0;
  double spacing_x_m = 0.0, spacing_y_m = 0.0;
};

/// The world's frame of a recorded ultrasound sample.
FrameView world_frame(const SimulatedWorld& world, const DeviceSample& sample);

/// I/O side: what one device sample becomes for the loop. A probe pose also goes to the
/// observer; an ultrasound frame (its pixels in `frame`) becomes the tumour point found in it,
/// delivered when the frame is, or nothing.
std::optional<DeviceSample> loop_sample(TumourObserver& observer, const DeviceSample& sample, const FrameView& frame);

/// The world's recording as the loop sees it: every frame replaced by its tumour point (or
/// left out), as the I/O thread does it; `counts` (optional) gets the observer's counts.
std::vector<DeviceSample> observed_recording(const SimulatedWorld& world, const TumourObserverOptions& options,
                                             ObserverCounts* counts = nullptr);

/// Median, p99, p99.9 and max of latencies (or step times) in microseconds.
LatencyStatistics latency_statistics(std::vector<double> latency_us);

/// A replay on a SimulatedClock at the loop's period.
struct StationReplay {
  std::vector<TickRecord> ticks;
  std::uint64_t output_hash = 0;  ///< FNV-1a of every tick's outputs (time, tumour now and ahead with covariances,
                                  ///< needle tip, diaphragm, phase)
};

/// Ticks the loop from 0 to duration_ns, each tick first pushing the samples delivered by
/// then; without `assimilate`, the tumour observations are left out.
Result<StationReplay> replay_station(const OperatingLoopModel& loop, std::span<const DeviceSample> samples,
                                     TimeNs duration_ns, bool assimilate);

/// RMS errors of a run's predictions against the world's truth, over its liver steps from `from_ns`.
struct PredictionErrors {
  double tumour_now_rms_m = 0.0;    ///< tumour estimate against the truth at its liver step
  double tumour_ahead_rms_m = 0.0;  ///< tumour ahead against the truth at that step + display latency
  double needle_tip_rms_m = 0.0;    ///< needle tip against the true tip at the tick
  int steps = 0;                    ///< liver steps counted
};

PredictionErrors prediction_errors(const SimulatedWorld& world, std::span<const TickRecord> ticks,
                                   TimeNs display_latency_ns, TimeNs from_ns);

}  // namespace nav::station
