// Costs of pose fusion on the real-time thread: a pose track's push and sample_at (inside
// the history, SLERP; after it, extrapolation), and the breathing predictor's push (one fit
// over its window) and predict. Each iteration times a batch of calls; the counters
// ns_median and ns_p99 are per call, over the batches.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <vector>

#include "nav/fusion/breathing_predictor.hpp"
#include "nav/fusion/pose_track.hpp"

namespace {

constexpr int kBatch = 32;

/// A tool going round a 5 cm circle once a second while turning once about a fixed axis:
/// periodic, so a table of one period of 1 kHz samples repeats without a jump.
nav::RigidPose moving_pose(nav::TimeNs time_ns) {
  const double angle_rad = 2.0 * 3.141592653589793 * static_cast<double>(time_ns % nav::kNsPerSecond) * 1e-9;
  return {Eigen::Vector3d(0.05 * std::cos(angle_rad), 0.05 * std::sin(angle_rad), 0.2),
          nav::quaternion_from_rotation_vector(Eigen::Vector3d(0.3, 1.0, -0.2).normalized() * angle_rad)};
}

/// Runs `call(i)` kBatch times per iteration and reports per-call median and p99 in ns.
template <typename Call>
void timed_batches(benchmark::State& state, Call&& call) {
  std::vector<double> ns;
  ns.reserve(1 << 20);
  std::int64_t i = 0;
  for (auto _ : state) {
    const auto start = std::chrono::steady_clock::now();
    for (int k = 0; k < kBatch; ++k, ++i) call(i);
    const double batch_ns = std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - start).count();
    if (ns.size() < ns.capacity()) ns.push_back(batch_ns / kBatch);
  }
  std::sort(ns.begin(), ns.end());
  state.counters["ns_median"] = ns[ns.size() / 2];
  state.counters["ns_p99"] = ns[std::min(ns.size() - 1, ns.size() * 99 / 100)];
  state.SetItemsProcessed(state.iterations() * kBatch);
}

/// A full 64-sample track of 1 kHz samples ending at `newest_ns`.
nav::PoseTrack filled_track(nav::TimeNs newest_ns) {
  nav::PoseTrack track = nav::PoseTrack::create({}).value();
  for (nav::TimeNs t = newest_ns - 63 * nav::kNsPerMs; t <= newest_ns; t += nav::kNsPerMs)
    track.push({t, moving_pose(t)});
  return track;
}

void BM_PoseTrackPush(benchmark::State& state) {
  std::vector<nav::RigidPose> poses;  // one period, made before timing
  for (nav::TimeNs t = 0; t < nav::kNsPerSecond; t += nav::kNsPerMs) poses.push_back(moving_pose(t));
  nav::PoseTrack track = filled_track(nav::kNsPerSecond);
  timed_batches(state, [&](std::int64_t i) {
    const nav::TimeNs t = nav::kNsPerSecond + (i + 1) * nav::kNsPerMs;
    benchmark::DoNotOptimize(track.push({t, poses[static_cast<std::size_t>((i + 1) % 1000)]}));
  });
  state.counters["healthy"] = track.degraded() ? 0.0 : 1.0;
}
BENCHMARK(BM_PoseTrackPush);

void BM_PoseTrackSampleAtInterpolated(benchmark::State& state) {
  const nav::TimeNs newest_ns = nav::kNsPerSecond;
  const nav::PoseTrack track = filled_track(newest_ns);
  timed_batches(state, [&](std::int64_t i) {
    benchmark::DoNotOptimize(track.sample_at(newest_ns - (i % 60) * nav::kNsPerMs - 400'000));
  });
}
BENCHMARK(BM_PoseTrackSampleAtInterpolated);

void BM_PoseTrackSampleAtExtrapolated(benchmark::State& state) {
  const nav::TimeNs newest_ns = nav::kNsPerSecond;
  const nav::PoseTrack track = filled_track(newest_ns);
  timed_batches(state,
                [&](std::int64_t i) { benchmark::DoNotOptimize(track.sample_at(newest_ns + 1 + i % 20'000'000)); });
}
BENCHMARK(BM_PoseTrackSampleAtExtrapolated);

/// A predictor that has seen 30 s of 40 Hz breathing (the window full and fitted).
nav::BreathingPredictor breathing_predictor(nav::TimeNs* next_ns) {
  nav::BreathingPredictor predictor = nav::BreathingPredictor::create({}).value();
  nav::TimeNs t = 0;
  for (; t < 30 * nav::kNsPerSecond; t += 25 * nav::kNsPerMs)
    predictor.push(t, 0.005 * std::sin(static_cast<double>(t) * 1.6e-9));
  *next_ns = t;
  return predictor;
}

void BM_BreathingPredictorPush(benchmark::State& state) {
  nav::TimeNs next_ns = 0;
  nav::BreathingPredictor predictor = breathing_predictor(&next_ns);
  timed_batches(state, [&](std::int64_t i) {
    const nav::TimeNs t = next_ns + i * 25 * nav::kNsPerMs;
    benchmark::DoNotOptimize(predictor.push(t, 0.005 * std::sin(static_cast<double>(t) * 1.6e-9)));
  });
}
BENCHMARK(BM_BreathingPredictorPush);

void BM_BreathingPredictorPredict(benchmark::State& state) {
  nav::TimeNs next_ns = 0;
  const nav::BreathingPredictor predictor = breathing_predictor(&next_ns);
  timed_batches(state, [&](std::int64_t i) {
    benchmark::DoNotOptimize(predictor.predict(next_ns + (i % 1000) * nav::kNsPerMs, 200 * nav::kNsPerMs));
  });
}
BENCHMARK(BM_BreathingPredictorPredict);

}  // namespace
