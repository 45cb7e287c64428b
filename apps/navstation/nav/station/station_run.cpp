#include "nav/station/station_run.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <memory>
#include <thread>

#include "nav/core/fixed_rate_timer.hpp"
#include "nav/core/fnv_hash.hpp"
#include "nav/mesh/geometry.hpp"
#include "nav/station/station_channels.hpp"
#include "nav/station/station_dds.hpp"

namespace nav::station {

namespace {

constexpr TimeNs kStartDelayNs = 20 * kNsPerMs;  // from the real-time setup to the first tick

/// Hands one recorded sample to the loop. Real-time safe.
void push_sample(const OperatingLoopModel& loop, OperatingLoopData& data, const DeviceSample& s,
                 bool assimilate) noexcept {
  switch (s.kind) {
    case SampleKind::needle_pose:
      push_needle_pose(loop, data, {s.measured_ns, s.pose});
      break;
    case SampleKind::probe_pose:
      push_probe_pose(loop, data, {s.measured_ns, s.pose});
      break;
    case SampleKind::respiratory:
      push_respiratory_sample(loop, data, s.measured_ns, s.point_m);
      break;
    case SampleKind::tumour:
      if (assimilate) push_tumour_observation(data, s.measured_ns, {s.point_m[0], s.point_m[1], s.point_m[2]});
      break;
    case SampleKind::ultrasound_frame:
      break;  // frames reach the loop as tumour points only
  }
}

TickRecord record_of(const OperatingLoopOutputs& o) noexcept {
  const Point3& f = o.needle_shape.tip_force_n;
  return {o.time_ns,
          o.tissue_time_ns,
          o.tumour_now_m,
          o.tumour_ahead_m,
          o.needle_tip_m,
          o.degraded,
          o.needle.degraded,
          o.needle.flags.bits(),
          health_flag_bits(o),
          std::sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]),
          o.needle_shape.punctures};
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

/// The real-time thread's preallocated records.
struct RealtimeRecords {
  std::vector<TickRecord> ticks;
  std::vector<double> step_us, lateness_us;
  std::int64_t count = 0;
  std::int64_t skipped = 0;
};

void realtime_thread(const OperatingLoopModel& loop, OperatingLoopData& data, StationChannels& ch, RealtimeRecords& rec,
                     const StationRunOptions& options, std::vector<SetupStep>& setup) {
  setup = apply_realtime_setup(options.realtime);
  ch.start_ns = ch.clock.now_ns() + kStartDelayNs;  // the first tick comes once the setup is done
  ch.started.store(true, std::memory_order_release);
  const TimeNs period = loop.options.tick_period_ns;
  FixedRateTimer timer(ch.clock, period, ch.start_ns);
  const auto capacity = static_cast<std::int64_t>(rec.ticks.size());
  const double miss_threshold_us = 1e-3 * static_cast<double>(options.miss_threshold_ns);
  const std::int64_t health_every_ticks = std::max<std::int64_t>(
      1, (options.dds ? options.dds->health_period_ns : kNsPerSecond) / loop.options.tick_period_ns);
  const OutputStamps stamps{ch.start_ns, loop.options.display_latency_ns,
                            options.dds ? options.dds->tools.needle : ToolIds{}.needle};
  std::uint64_t misses = 0;
  TimeNs window_max_ns = 0;
  DeviceSample sample;
  while (rec.count < capacity) {
    const Tick tick = timer.wait_next_tick();
    if (tick.deadline_ns - ch.start_ns > options.duration_ns) break;
    if (options.stop != nullptr && options.stop->load(std::memory_order_relaxed)) break;
    const TimeNs begin = ch.clock.now_ns();
    while (ch.samples.try_pop(sample)) push_sample(loop, data, sample, true);
    nav::tick(loop, data, begin - ch.start_ns);
    ch.outputs.write(data.outputs);
    const auto i = static_cast<std::size_t>(rec.count++);
    rec.ticks[i] = record_of(data.outputs);
    rec.lateness_us[i] = 1e-3 * static_cast<double>(tick.lateness_ns + tick.skipped * period);
    const TimeNs step_ns = ch.clock.now_ns() - begin;
    rec.step_us[i] = 1e-3 * static_cast<double>(step_ns);
    if (ch.outbox != nullptr) {
      if (rec.lateness_us[i] > miss_threshold_us) ++misses;
      window_max_ns = std::max(window_max_ns, step_ns);
      push_outputs(*ch.outbox, data.outputs, stamps, health_every_ticks, misses, window_max_ns);
      if (data.outputs.ticks % health_every_ticks == 0) window_max_ns = 0;
    }
  }
  rec.skipped = timer.skipped_ticks();
  ch.realtime_done.store(true, std::memory_order_release);
}

/// The direct hand-off: the world's recording played in real time.
void io_thread(const SimulatedWorld& world, StationChannels& ch, StationRun& run, const StationRunOptions& options) {
  setup_io_thread(options, run);
  TumourObserver observer(world.imaging, options.observer);
  ch.wait_for_start();
  std::size_t next = 0;
  // Takes the samples delivered by run time `now`, handing them to the loop while it runs.
  const auto take_samples_until = [&](TimeNs now, bool loop_running) {
    for (; next < world.samples.size() && world.samples[next].delivered_ns <= now; ++next) {
      const DeviceSample& s = world.samples[next];
      const std::optional<DeviceSample> for_loop = loop_sample(observer, s, world_frame(world, s));
      if (!for_loop) continue;
      if (!loop_running)
        ++run.samples_after_loop;
      else if (ch.samples.try_push(*for_loop))
        ++run.samples_pushed;
    }
  };
  while (!ch.realtime_done.load(std::memory_order_acquire)) {
    take_samples_until(ch.run_time_ns(), true);
    if (ch.outputs.update()) ++run.outputs_read;
    ch.clock.sleep_until_ns(ch.clock.now_ns() + kIoPeriodNs);
  }
  take_samples_until(options.duration_ns, false);
  run.observer = observer.counts();
  run.frame_processing = latency_statistics(observer.processing_us());
}

}  // namespace

void setup_io_thread(const StationRunOptions& options, StationRun& run) {
  run.io_pin = pin_to_core(options.io_core);
  if (options.io_priority > 0) run.io_fifo = request_fifo(options.io_priority);
}

StepStatistics step_statistics(std::vector<double> step_us, const std::vector<double>& lateness_us,
                               double miss_threshold_us) {
  StepStatistics s;
  const LatencyStatistics step = latency_statistics(std::move(step_us));
  s.ticks = step.count;
  if (s.ticks == 0) return s;
  s.median_us = step.median_us;
  s.p99_us = step.p99_us;
  s.p999_us = step.p999_us;
  s.p9999_us = step.p9999_us;
  s.max_us = step.max_us;
  double sum = 0.0, sum2 = 0.0;
  for (std::size_t i = 0; i < lateness_us.size(); ++i) {
    const double late = lateness_us[i];
    sum += late;
    sum2 += late * late;
    if (late > s.max_lateness_us) s.max_lateness_us = late, s.latest_tick = static_cast<std::int64_t>(i);
    if (late > miss_threshold_us) ++s.deadline_misses;
    if (late > 1000.0) ++s.late_over_1ms;
  }
  const double n = static_cast<double>(lateness_us.size());
  s.jitter_us = std::sqrt(std::max(0.0, sum2 / n - (sum / n) * (sum / n)));
  const LatencyStatistics lateness = latency_statistics(lateness_us);
  s.lateness_p99_us = lateness.p99_us;
  s.lateness_p9999_us = lateness.p9999_us;
  return s;
}

namespace {

/// The run's two threads, the I/O one on DDS when options.dds is set: with a `world`, its
/// devices play its recording in this process; without, the devices are other processes.
Result<StationRun> run_threads(const OperatingLoopModel& loop, const SimulatedWorld* world, const ProbeImaging& imaging,
                               const StationRunOptions& options) {
  auto data = make_operating_loop_data(loop);
  if (!data.ok()) return data.error();
  const auto capacity = static_cast<std::size_t>(options.duration_ns / loop.options.tick_period_ns + 2);
  RealtimeRecords rec;
  rec.ticks.resize(capacity);
  rec.step_us.resize(capacity);
  rec.lateness_us.resize(capacity);
  auto channels = std::make_unique<StationChannels>();
  std::unique_ptr<dds::StationOutbox> outbox;
  std::unique_ptr<StationDdsLink> link;
  if (options.dds) {
    const DdsRunOptions& o = *options.dds;
    auto created = StationDdsLink::create(o.domain_id, o.topic_names, o.arrival, o.pose_bounds, world != nullptr,
                                          o.network, o.tools);
    if (!created.ok()) return created.error();
    link = std::move(created).value();
    outbox = std::make_unique<dds::StationOutbox>();
    channels->outbox = outbox.get();
  }
  StationRun run;
  std::thread realtime(realtime_thread, std::cref(loop), std::ref(data.value()), std::ref(*channels), std::ref(rec),
                       std::cref(options), std::ref(run.realtime_setup));
  std::thread io =
      link ? std::thread(dds_io_thread, std::cref(loop), world, std::cref(imaging), std::ref(*channels), std::ref(run),
                         std::cref(options), std::ref(*link))
           : std::thread(io_thread, std::cref(*world), std::ref(*channels), std::ref(run), std::cref(options));
  realtime.join();
  io.join();
  run.start_ns = channels->start_ns;
  const auto n = static_cast<std::size_t>(rec.count);
  rec.step_us.resize(n);
  rec.lateness_us.resize(n);
  rec.ticks.resize(n);
  run.steps =
      step_statistics(std::move(rec.step_us), rec.lateness_us, 1e-3 * static_cast<double>(options.miss_threshold_ns));
  run.steps.skipped_ticks = rec.skipped;
  run.ticks = std::move(rec.ticks);
  return run;
}

}  // namespace

Result<StationRun> run_station(const OperatingLoopModel& loop, const SimulatedWorld& world,
                               const StationRunOptions& options) {
  return run_threads(loop, &world, world.imaging, options);
}

Result<StationRun> run_live_station(const OperatingLoopModel& loop, const ProbeImaging& imaging,
                                    const StationRunOptions& options) {
  if (!options.dds)
    return Error{.message = "a live station reads its devices on DDS: it needs DDS run options", .field = "dds"};
  return run_threads(loop, nullptr, imaging, options);
}

std::uint32_t health_flag_bits(const OperatingLoopOutputs& o) noexcept {
  HealthFlags flags = o.tissue;
  for (const InputStatus* input : {&o.needle, &o.probe, &o.respiratory, &o.ultrasound}) flags.merge(input->flags);
  flags.merge(o.loop);
  return flags.bits();
}

FrameView world_frame(const SimulatedWorld& world, const DeviceSample& sample) {
  if (sample.frame_index < 0) return {};
  const ultrasound::BmodeGeometry& g = world.imaging.geometry;
  return {world.frames[static_cast<std::size_t>(sample.frame_index)].pixels.data(), g.width_px, g.height_px,
          g.spacing_m, g.spacing_m};
}

std::optional<DeviceSample> loop_sample(TumourObserver& observer, const DeviceSample& sample, const FrameView& frame) {
  if (sample.kind == SampleKind::probe_pose) observer.add_probe_pose(sample.measured_ns, sample.pose);
  if (sample.kind != SampleKind::ultrasound_frame) return sample;
  const std::optional<Eigen::Vector3d> tumour = observer.observe(sample.measured_ns, frame.pixels, frame.width_px,
                                                                 frame.height_px, frame.spacing_x_m, frame.spacing_y_m);
  if (!tumour) return std::nullopt;
  DeviceSample seen = sample;
  seen.kind = SampleKind::tumour;
  seen.point_m = *tumour;
  seen.frame_index = -1;
  return seen;
}

std::vector<DeviceSample> observed_recording(const SimulatedWorld& world, const TumourObserverOptions& options,
                                             ObserverCounts* counts) {
  TumourObserver observer(world.imaging, options);
  std::vector<DeviceSample> observed;
  observed.reserve(world.samples.size());
  for (const DeviceSample& s : world.samples) {
    if (std::optional<DeviceSample> for_loop = loop_sample(observer, s, world_frame(world, s)))
      observed.push_back(*for_loop);
  }
  if (counts != nullptr) *counts = observer.counts();
  return observed;
}

LatencyStatistics latency_statistics(std::vector<double> latency_us) {
  LatencyStatistics s;
  s.count = static_cast<std::int64_t>(latency_us.size());
  if (latency_us.empty()) return s;
  std::sort(latency_us.begin(), latency_us.end());
  s.median_us = percentile(latency_us, 0.5);
  s.p99_us = percentile(latency_us, 0.99);
  s.p999_us = percentile(latency_us, 0.999);
  s.p9999_us = percentile(latency_us, 0.9999);
  s.max_us = latency_us.back();
  return s;
}

Result<StationReplay> replay_station(const OperatingLoopModel& loop, std::span<const DeviceSample> samples,
                                     TimeNs duration_ns, bool assimilate) {
  auto data = make_operating_loop_data(loop);
  if (!data.ok()) return data.error();
  StationReplay replay;
  replay.output_hash = kFnvOffsetBasis;
  replay.ticks.reserve(static_cast<std::size_t>(duration_ns / loop.options.tick_period_ns + 1));
  SimulatedClock clock(0);
  std::size_t next = 0;
  while (clock.now_ns() <= duration_ns) {
    const TimeNs now = clock.now_ns();
    for (; next < samples.size() && samples[next].delivered_ns <= now; ++next)
      push_sample(loop, data.value(), samples[next], assimilate);
    tick(loop, data.value(), now);
    replay.ticks.push_back(record_of(data.value().outputs));
    replay.output_hash = hash_outputs(replay.output_hash, data.value().outputs);
    clock.advance_ns(loop.options.tick_period_ns);
  }
  return replay;
}

PredictionErrors prediction_errors(const SimulatedWorld& world, std::span<const TickRecord> ticks,
                                   TimeNs display_latency_ns, TimeNs from_ns) {
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
