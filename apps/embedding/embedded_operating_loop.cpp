// Station software embedding navrt's operating loop without DDS. Its own threads stand for its
// drivers: a tracker (needle marker, probe marker and respiratory marker at 60 Hz, measured
// 10 ms before they arrive) and an ultrasound tumour detector (a tumour point at 20 Hz, 30 ms
// after capture), each handing timestamped samples to the real-time thread through a
// lock-free single-producer ring. The real-time thread runs the loop at 1 kHz on a
// FixedRateTimer: it drains the rings into push_*, ticks, and publishes the outputs through a
// triple buffer, which the main thread reads as a display would: the tumour now and 50 ms
// ahead with covariance, the needle tip, the health. The patient is simulated (the full-order
// liver is the truth); the example prints the loop's timing and its error against that truth.
//   embedded_operating_loop [SECONDS (6)] [MISS_MS (5): a tick later than this is a deadline miss]
// Its last line, "figures: M T U NOW AHEAD MARKER TIP F D", repeats the misses, the tracker
// samples and tumour points pushed, the RMS errors (mm: tumour now, ahead, marker only, needle
// tip), whether every output was finite (1) and whether the last one was degraded (1).
#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <thread>
#include <vector>

#include "nav/core/clock.hpp"
#include "nav/core/fixed_rate_timer.hpp"
#include "nav/core/spsc_ring.hpp"
#include "nav/core/triple_buffer.hpp"
#include "nav/loop/operating_loop.hpp"
#include "simulated_patient.hpp"
#include "station_liver_loop.hpp"

namespace {

using nav::seconds_of;
using nav::TimeNs;

constexpr TimeNs kTrackerPeriodNs = nav::kNsPerSecond / 60;
constexpr TimeNs kTrackerDelayNs = 10 * nav::kNsPerMs;
constexpr TimeNs kUltrasoundPeriodNs = 50 * nav::kNsPerMs;
constexpr TimeNs kUltrasoundDelayNs = 30 * nav::kNsPerMs;
constexpr TimeNs kSettledNs = nav::kNsPerSecond;  // errors are scored from here (the filter's start-up)

/// One tracker measurement as the tracker driver hands it over.
struct TrackerSample {
  enum class Tool { needle, probe, respiratory } tool = Tool::needle;
  TimeNs time_ns = 0;  ///< measurement time (run time)
  nav::RigidPose pose;
};

/// One tumour point found by the ultrasound detector (model frame).
struct TumourPoint {
  TimeNs time_ns = 0;  ///< capture time (run time)
  nav::Point3 position_m{};
};

/// What the threads share: the rings into the real-time thread, its outputs, the clock.
struct Shared {
  nav::SpscRing<TrackerSample, 256> tracker;
  nav::SpscRing<TumourPoint, 64> ultrasound;
  nav::TripleBuffer<nav::OperatingLoopOutputs> outputs;
  nav::MonotonicClock clock;
  TimeNs start_ns = 0;
  std::atomic<bool> done{false};
};

/// The tracker driver: every period, the three markers as measured kTrackerDelayNs ago.
void tracker_thread(Shared& shared, const embedding::PatientMotion& motion, const nav::RigidPose& probe) {
  embedding::DeviceNoise noise(1, 0.25e-3);
  nav::FixedRateTimer timer(shared.clock, kTrackerPeriodNs, shared.start_ns + kTrackerDelayNs);
  while (!shared.done.load(std::memory_order_acquire)) {
    const TimeNs measured_ns = timer.wait_next_tick().deadline_ns - shared.start_ns - kTrackerDelayNs;
    const double t_s = seconds_of(measured_ns);
    TrackerSample needle{TrackerSample::Tool::needle, measured_ns, motion.needle_marker(t_s)};
    needle.pose.position_m += noise();
    TrackerSample probe_sample{TrackerSample::Tool::probe, measured_ns, probe};
    probe_sample.pose.position_m += noise();
    TrackerSample marker{TrackerSample::Tool::respiratory, measured_ns, {}};
    marker.pose.position_m = Eigen::Vector3d(0.0, 0.15, motion.marker_rest_z_m + motion.marker_rise_m(t_s)) + noise();
    for (const TrackerSample& s : {needle, probe_sample, marker}) shared.tracker.try_push(s);
  }
}

/// The ultrasound tumour detector: every frame, the tumour captured kUltrasoundDelayNs ago.
void ultrasound_thread(Shared& shared, const embedding::PatientMotion& motion, const embedding::TumourTruth& truth) {
  embedding::DeviceNoise noise(2, 1e-3);
  nav::FixedRateTimer timer(shared.clock, kUltrasoundPeriodNs, shared.start_ns + kUltrasoundDelayNs);
  while (!shared.done.load(std::memory_order_acquire)) {
    const TimeNs captured_ns = timer.wait_next_tick().deadline_ns - shared.start_ns - kUltrasoundDelayNs;
    const Eigen::Vector3d seen = truth.at(motion.diaphragm_lift_m(seconds_of(captured_ns))) + noise();
    shared.ultrasound.try_push({captured_ns, {seen[0], seen[1], seen[2]}});
  }
}

/// What the real-time thread measures about itself, in preallocated arrays.
struct RealtimeRecord {
  std::vector<double> step_us, lateness_us;
  std::int64_t ticks = 0, tracker_samples = 0, tumour_points = 0;
};

/// The real-time thread: drain, tick, publish, at 1 kHz. Nothing here allocates, locks or
/// makes a system call but the timer's sleep (station software pins it to its own core).
void realtime_thread(Shared& shared, const nav::OperatingLoopModel& loop, nav::OperatingLoopData& data,
                     RealtimeRecord& record) {
  nav::FixedRateTimer timer(shared.clock, loop.options.tick_period_ns, shared.start_ns);
  TrackerSample sample;
  TumourPoint point;
  while (record.ticks < static_cast<std::int64_t>(record.step_us.size())) {
    const nav::Tick tick = timer.wait_next_tick();
    const TimeNs begin_ns = shared.clock.now_ns();
    for (; shared.tracker.try_pop(sample); ++record.tracker_samples) {
      if (sample.tool == TrackerSample::Tool::needle) nav::push_needle_pose(loop, data, {sample.time_ns, sample.pose});
      if (sample.tool == TrackerSample::Tool::probe) nav::push_probe_pose(loop, data, {sample.time_ns, sample.pose});
      if (sample.tool == TrackerSample::Tool::respiratory)
        nav::push_respiratory_sample(loop, data, sample.time_ns, sample.pose.position_m);
    }
    for (; shared.ultrasound.try_pop(point); ++record.tumour_points)
      nav::push_tumour_observation(data, point.time_ns, point.position_m);
    nav::tick(loop, data, begin_ns - shared.start_ns);
    shared.outputs.write(data.outputs);
    const auto i = static_cast<std::size_t>(record.ticks++);
    record.step_us[i] = 1e-3 * static_cast<double>(shared.clock.now_ns() - begin_ns);
    record.lateness_us[i] = 1e-3 * static_cast<double>(tick.lateness_ns + tick.skipped * loop.options.tick_period_ns);
  }
  shared.done.store(true, std::memory_order_release);
}

/// The main thread's view: errors of the outputs against the truth at every liver step.
struct Scores {
  double now2 = 0.0, ahead2 = 0.0, marker2 = 0.0, tip2 = 0.0;
  int steps = 0;
  std::int64_t last_step = -1;
  bool finite = true;
  TimeNs ready_ns = -1;  ///< the first tick with no input degraded and no flag raised
};

Eigen::Vector3d vec(const nav::Point3& p) { return {p[0], p[1], p[2]}; }

void score(const nav::OperatingLoopOutputs& o, const embedding::PatientMotion& motion,
           const embedding::TumourTruth& truth, TimeNs latency_ns, Scores& s) {
  for (const nav::Point3* p : {&o.tumour_now_m, &o.tumour_ahead_m, &o.needle_tip_m})
    s.finite = s.finite && std::isfinite((*p)[0]) && std::isfinite((*p)[1]) && std::isfinite((*p)[2]);
  if (s.ready_ns < 0 && !o.degraded) s.ready_ns = o.time_ns;
  if (o.tissue_steps == s.last_step || o.tissue_time_ns < kSettledNs) return;
  s.last_step = o.tissue_steps;
  const double t_s = seconds_of(o.tissue_time_ns);
  const Eigen::Vector3d tumour = truth.at(motion.diaphragm_lift_m(t_s));
  s.now2 += (vec(o.tumour_now_m) - tumour).squaredNorm();
  s.ahead2 += (vec(o.tumour_ahead_m) - truth.at(motion.diaphragm_lift_m(t_s + seconds_of(latency_ns)))).squaredNorm();
  s.marker2 += (truth.at(motion.marker_rise_m(t_s)) - tumour).squaredNorm();  // the liver following the marker exactly
  s.tip2 += (vec(o.needle_tip_m) - motion.needle_tip_m(seconds_of(o.time_ns))).squaredNorm();
  ++s.steps;
}

double percentile(std::vector<double> values, double fraction) {
  std::sort(values.begin(), values.end());
  return values[static_cast<std::size_t>(fraction * static_cast<double>(values.size() - 1))];
}

double rms_mm(double sum2, int n) { return 1e3 * std::sqrt(sum2 / std::max(n, 1)); }

int fail(const char* what, const nav::Error& error) {
  std::fprintf(stderr, "embedded_operating_loop: %s: %s\n", what, error.describe().c_str());
  return 1;
}

/// The square root of a covariance's trace, in millimetres.
double sd_mm(const std::array<double, 9>& covariance_m2) {
  return 1e3 * std::sqrt(covariance_m2[0] + covariance_m2[4] + covariance_m2[8]);
}

}  // namespace

int main(int argc, char** argv) {
  const double run_s = argc > 1 ? std::strtod(argv[1], nullptr) : 6.0;
  const double miss_ms = argc > 2 ? std::strtod(argv[2], nullptr) : 5.0;
  if (!(run_s > 0.0 && run_s <= 600.0) || !(miss_ms > 0.0)) {
    std::fprintf(stderr, "usage: embedded_operating_loop [SECONDS in (0, 600]] [MISS_MS > 0]\n");
    return 2;
  }
  // Start-up: may allocate and fail with a clear error.
  const auto begin = std::chrono::steady_clock::now();
  auto liver = embedding::make_liver(0.02);
  if (!liver.ok()) return fail("liver", liver.error());
  embedding::PatientMotion motion;
  motion.needle_entry_m =
      liver.value().tumour_rest_m + Eigen::Vector3d(0.0, 0.06, 0.0);  // 6 cm anterior, inserted toward it
  embedding::LoopSettings settings;
  settings.respiratory_reference_m = motion.marker_rest_z_m;
  auto loop = embedding::make_loop(liver.value(), settings);
  if (!loop.ok()) return fail("loop", loop.error());
  auto data = nav::make_operating_loop_data(loop.value());
  if (!data.ok()) return fail("loop data", data.error());
  const double build_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
  auto truth = embedding::TumourTruth::solve(liver.value(), 0.012, 25);
  if (!truth.ok()) return fail("truth", truth.error());
  std::printf("liver: %zu tetrahedra, %d vibration modes with corotational cubature; loop built in %.2f s\n",
              liver.value().mesh.tets.size(), loop.value().rungs.front().reduced.basis_size(), build_s);

  auto shared = std::make_unique<Shared>();
  const auto ticks = static_cast<std::size_t>(run_s * 1e9 / static_cast<double>(loop.value().options.tick_period_ns));
  RealtimeRecord record{std::vector<double>(ticks), std::vector<double>(ticks)};
  const nav::RigidPose probe{liver.value().tumour_rest_m + Eigen::Vector3d(0.0, 0.045, 0.0),
                             Eigen::Quaterniond::Identity()};
  shared->start_ns = shared->clock.now_ns() + 20 * nav::kNsPerMs;
  std::thread realtime(realtime_thread, std::ref(*shared), std::cref(loop.value()), std::ref(data.value()),
                       std::ref(record));
  std::thread tracker(tracker_thread, std::ref(*shared), std::cref(motion), std::cref(probe));
  std::thread ultrasound(ultrasound_thread, std::ref(*shared), std::cref(motion), std::cref(truth.value()));

  // The rest of the station software: reads the newest outputs whenever it likes (every 2 ms).
  Scores scores;
  nav::OperatingLoopOutputs last;
  const TimeNs latency_ns = loop.value().options.display_latency_ns;
  while (!shared->done.load(std::memory_order_acquire)) {
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
    if (shared->outputs.update()) score(shared->outputs.read(), motion, truth.value(), latency_ns, scores);
  }
  realtime.join();
  tracker.join();
  ultrasound.join();
  if (shared->outputs.update()) score(shared->outputs.read(), motion, truth.value(), latency_ns, scores);
  last = shared->outputs.read();

  const auto misses = std::count_if(record.lateness_us.begin(), record.lateness_us.end(),
                                    [&](double late) { return late > 1e3 * miss_ms; });
  std::printf("ran %lld ticks at 1 kHz: step median %.1f us, p99 %.1f us, max %.1f us; lateness max %.1f us\n",
              static_cast<long long>(record.ticks), percentile(record.step_us, 0.5), percentile(record.step_us, 0.99),
              percentile(record.step_us, 1.0), percentile(record.lateness_us, 1.0));
  std::printf("deadline misses (> %.0f ms late): %lld\n", miss_ms, static_cast<long long>(misses));
  std::printf("pushed: %lld tracker samples, %lld tumour points\n", static_cast<long long>(record.tracker_samples),
              static_cast<long long>(record.tumour_points));
  std::printf(
      "tumour error against the full-order liver (RMS over %d liver steps from 1 s): now %.2f mm, at +%.0f ms %.2f mm; "
      "marker only %.2f mm\n",
      scores.steps, rms_mm(scores.now2, scores.steps), 1e-6 * static_cast<double>(latency_ns),
      rms_mm(scores.ahead2, scores.steps), rms_mm(scores.marker2, scores.steps));
  std::printf("needle tip error: %.2f mm RMS\n", rms_mm(scores.tip2, scores.steps));
  const Eigen::Vector3d now_mm = 1e3 * vec(last.tumour_now_m), ahead_mm = 1e3 * vec(last.tumour_ahead_m),
                        tip_mm = 1e3 * vec(last.needle_tip_m);
  std::printf(
      "last outputs at %.3f s: tumour now (%.1f, %.1f, %.1f) mm, sd %.2f mm; ahead (%.1f, %.1f, %.1f) mm, sd %.2f mm\n",
      seconds_of(last.time_ns), now_mm[0], now_mm[1], now_mm[2], sd_mm(last.tumour_now_covariance_m2), ahead_mm[0],
      ahead_mm[1], ahead_mm[2], sd_mm(last.tumour_ahead_covariance_m2));
  std::printf("  needle tip (%.1f, %.1f, %.1f) mm, %.1f mm from the tumour\n", tip_mm[0], tip_mm[1], tip_mm[2],
              1e3 * last.tip_to_tumour_m);
  std::printf(
      "  health: degraded %s; flags needle 0x%x, probe 0x%x, respiratory 0x%x, ultrasound 0x%x, tissue 0x%x, loop "
      "0x%x\n",
      last.degraded ? "yes" : "no", last.needle.flags.bits(), last.probe.flags.bits(), last.respiratory.flags.bits(),
      last.ultrasound.flags.bits(), last.tissue.bits(), last.loop.bits());
  std::printf("outputs finite: %s; first tick with nothing degraded at %.3f s\n", scores.finite ? "yes" : "no",
              seconds_of(scores.ready_ns));
  // The same figures on one line, for scripts and tests.
  std::printf("figures: %lld %lld %lld %.4f %.4f %.4f %.4f %d %d\n", static_cast<long long>(misses),
              static_cast<long long>(record.tracker_samples), static_cast<long long>(record.tumour_points),
              rms_mm(scores.now2, scores.steps), rms_mm(scores.ahead2, scores.steps),
              rms_mm(scores.marker2, scores.steps), rms_mm(scores.tip2, scores.steps), scores.finite ? 1 : 0,
              last.degraded ? 1 : 0);
  return scores.finite ? 0 : 1;
}
