#include "nav/station/station_run.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <memory>
#include <thread>

#include "nav/core/fixed_rate_timer.hpp"
#include "nav/core/fnv_hash.hpp"
#include "nav/core/spsc_ring.hpp"
#include "nav/core/triple_buffer.hpp"
#include "nav/mesh/geometry.hpp"

namespace nav::station {

namespace {

constexpr std::size_t kRingCapacity = 1024;            // samples in flight from the I/O thread
constexpr TimeNs kStartDelayNs = 20 * kNsPerMs;        // from the real-time setup to the first tick
constexpr TimeNs kIoPeriodNs = kNsPerMs / 2;           // the I/O thread's polling period

/// Hands one recorded sample to the loop. Real-time safe.
void push_sample(const OperatingLoopModel& loop, OperatingLoopData& data, const DeviceSample& s, bool assimilate) noexcept {
  switch (s.kind) {
    case SampleKind::needle_pose: push_needle_pose(loop, data, {s.measured_ns, s.pose}); break;
    case SampleKind::probe_pose: push_probe_pose(loop, data, {s.measured_ns, s.pose}); break;
    case SampleKind::respiratory: push_respiratory_sample(loop, data, s.measured_ns, s.point_m); break;
    case SampleKind::tumour:
      if (assimilate) push_tumour_observation(data, s.measured_ns, {s.point_m[0], s.point_m[1], s.point_m[2]});
      break;
  }
}

TickRecord record_of(const OperatingLoopOutputs& o) noexcept {
  return {o.time_ns, o.tissue_time_ns, o.tumour_now_m, o.tumour_ahead_m, o.needle_tip_m};
}

template <class T>
std::uint64_t hash_value(std::uint64_t hash, const T& value) noexcept {
  return fnv1a(hash, &value, sizeof(value));
}

std::uint64_t hash_outputs(std::uint64_t hash, const OperatingLoopOutputs& o) noexcept {
  hash = hash_value(hash, o.time_ns);
  hash = hash_value(hash, o.tissue_time_ns);
  hash = hash_value(hash, o.tumour_now_m);
  hash = hash_value(hash, o.tumour_now_covariance_m2);
  hash = hash_value(hash, o.tumour_ahead_m);
  hash = hash_value(hash, o.tumour_ahead_covariance_m2);
  hash = hash_value(hash, o.needle_tip_m);
  hash = hash_value(hash, o.needle_tip_ahead_m);
  hash = hash_value(hash, o.diaphragm_m);
  return hash_value(hash, o.breathing_phase_rad);
}

double percentile(const std::vector<double>& sorted, double fraction) {
  const auto i = static_cast<std::size_t>(fraction * static_cast<double>(sorted.size() - 1) + 0.5);
  return sorted[std::min(i, sorted.size() - 1)];
}

double squared_distance(const Point3& a, const Point3& b) { return dot(a - b, a - b); }

/// What the two threads share: the ring, the triple buffer, the clock and the start time.
struct Channels {
  SpscRing<DeviceSample, kRingCapacity> samples;
  TripleBuffer<OperatingLoopOutputs> outputs;
  MonotonicClock clock;
  TimeNs start_ns = 0;               ///< written by the real-time thread before `started`
  std::atomic<bool> started{false};
  std::atomic<bool> realtime_done{false};
};

/// The real-time thread's preallocated records.
struct RealtimeRecords {
  std::vector<TickRecord> ticks;
  std::vector<double> step_us, lateness_us;
  std::int64_t count = 0;
  std::int64_t skipped = 0;
};

void realtime_thread(const OperatingLoopModel& loop, OperatingLoopData& data, Channels& ch, RealtimeRecords& rec,
                     const StationRunOptions& options, std::vector<SetupStep>& setup) {
  setup = apply_realtime_setup(options.realtime);
  ch.start_ns = ch.clock.now_ns() + kStartDelayNs;  // the first tick comes once the setup is done
  ch.started.store(true, std::memory_order_release);
  const TimeNs period = loop.options.tick_period_ns;
  FixedRateTimer timer(ch.clock, period, ch.start_ns);
  const auto capacity = static_cast<std::int64_t>(rec.ticks.size());
  DeviceSample sample;
  while (rec.count < capacity) {
    const Tick tick = timer.wait_next_tick();
    if (tick.deadline_ns - ch.start_ns > options.duration_ns) break;
    const TimeNs begin = ch.clock.now_ns();
    while (ch.samples.try_pop(sample)) push_sample(loop, data, sample, true);
    nav::tick(loop, data, begin - ch.start_ns);
    ch.outputs.write(data.outputs);
    const auto i = static_cast<std::size_t>(rec.count++);
    rec.ticks[i] = record_of(data.outputs);
    rec.lateness_us[i] = 1e-3 * static_cast<double>(tick.lateness_ns + tick.skipped * period);
    rec.step_us[i] = 1e-3 * static_cast<double>(ch.clock.now_ns() - begin);
  }
  rec.skipped = timer.skipped_ticks();
  ch.realtime_done.store(true, std::memory_order_release);
}

void io_thread(const SimulatedWorld& world, Channels& ch, StationRun& run, int core) {
  run.io_pin = pin_to_core(core);
  while (!ch.started.load(std::memory_order_acquire)) ch.clock.sleep_until_ns(ch.clock.now_ns() + kIoPeriodNs);
  std::size_t next = 0;
  while (!ch.realtime_done.load(std::memory_order_acquire)) {
    const TimeNs now = ch.clock.now_ns() - ch.start_ns;
    while (next < world.samples.size() && world.samples[next].delivered_ns <= now && ch.samples.try_push(world.samples[next])) {
      ++next;
      ++run.samples_pushed;
    }
    if (ch.outputs.update()) ++run.outputs_read;
    ch.clock.sleep_until_ns(ch.clock.now_ns() + kIoPeriodNs);
  }
}

}  // namespace

StepStatistics step_statistics(std::vector<double> step_us, const std::vector<double>& lateness_us, double miss_threshold_us) {
  StepStatistics s;
  s.ticks = static_cast<std::int64_t>(step_us.size());
  if (step_us.empty()) return s;
  std::sort(step_us.begin(), step_us.end());
  s.median_us = percentile(step_us, 0.5);
  s.p99_us = percentile(step_us, 0.99);
  s.p999_us = percentile(step_us, 0.999);
  s.max_us = step_us.back();
  double sum = 0.0, sum2 = 0.0;
  for (std::size_t i = 0; i < lateness_us.size(); ++i) {
    const double late = lateness_us[i];
    sum += late;
    sum2 += late * late;
    if (late > s.max_lateness_us) s.max_lateness_us = late, s.latest_tick = static_cast<std::int64_t>(i);
    if (late > miss_threshold_us) ++s.deadline_misses;
  }
  const double n = static_cast<double>(lateness_us.size());
  s.jitter_us = std::sqrt(std::max(0.0, sum2 / n - (sum / n) * (sum / n)));
  return s;
}

Result<StationRun> run_station(const OperatingLoopModel& loop, const SimulatedWorld& world, const StationRunOptions& options) {
  auto data = make_operating_loop_data(loop);
  if (!data.ok()) return data.error();
  const auto capacity = static_cast<std::size_t>(options.duration_ns / loop.options.tick_period_ns + 2);
  RealtimeRecords rec;
  rec.ticks.resize(capacity);
  rec.step_us.resize(capacity);
  rec.lateness_us.resize(capacity);
  auto channels = std::make_unique<Channels>();
  StationRun run;
  std::thread realtime(realtime_thread, std::cref(loop), std::ref(data.value()), std::ref(*channels), std::ref(rec), std::cref(options),
                       std::ref(run.realtime_setup));
  std::thread io(io_thread, std::cref(world), std::ref(*channels), std::ref(run), options.io_core);
  realtime.join();
  io.join();
  const auto n = static_cast<std::size_t>(rec.count);
  rec.step_us.resize(n);
  rec.lateness_us.resize(n);
  rec.ticks.resize(n);
  run.steps = step_statistics(std::move(rec.step_us), rec.lateness_us, 1e-3 * static_cast<double>(options.miss_threshold_ns));
  run.steps.skipped_ticks = rec.skipped;
  run.ticks = std::move(rec.ticks);
  return run;
}

Result<StationReplay> replay_station(const OperatingLoopModel& loop, std::span<const DeviceSample> samples, TimeNs duration_ns,
                                     bool assimilate) {
  auto data = make_operating_loop_data(loop);
  if (!data.ok()) return data.error();
  StationReplay replay;
  replay.output_hash = kFnvOffsetBasis;
  replay.ticks.reserve(static_cast<std::size_t>(duration_ns / loop.options.tick_period_ns + 1));
  SimulatedClock clock(0);
  std::size_t next = 0;
  while (clock.now_ns() <= duration_ns) {
    const TimeNs now = clock.now_ns();
    for (; next < samples.size() && samples[next].delivered_ns <= now; ++next) push_sample(loop, data.value(), samples[next], assimilate);
    tick(loop, data.value(), now);
    replay.ticks.push_back(record_of(data.value().outputs));
    replay.output_hash = hash_outputs(replay.output_hash, data.value().outputs);
    clock.advance_ns(loop.options.tick_period_ns);
  }
  return replay;
}

PredictionErrors prediction_errors(const SimulatedWorld& world, std::span<const TickRecord> ticks, TimeNs display_latency_ns,
                                   TimeNs from_ns) {
  PredictionErrors e;
  double now2 = 0.0, ahead2 = 0.0, tip2 = 0.0;
  for (const TickRecord& t : ticks) {
    if (t.time_ns < from_ns || t.time_ns != t.tissue_time_ns) continue;
    now2 += squared_distance(t.tumour_now_m, world.tumour_at(t.tissue_time_ns));
    ahead2 += squared_distance(t.tumour_ahead_m, world.tumour_at(t.tissue_time_ns + display_latency_ns));
    const Eigen::Vector3d tip = world.needle_tip_at(t.time_ns);
    tip2 += squared_distance(t.needle_tip_m, {tip[0], tip[1], tip[2]});
    ++e.steps;
  }
  if (e.steps == 0) return e;
  const double n = e.steps;
  e.tumour_now_rms_m = std::sqrt(now2 / n);
  e.tumour_ahead_rms_m = std::sqrt(ahead2 / n);
  e.needle_tip_rms_m = std::sqrt(tip2 / n);
  return e;
}

}  // namespace nav::station
