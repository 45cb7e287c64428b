// The simulated tracker: delivery at the configured rate and latency, noise with the
// configured spread, dropouts at the configured rate, the same samples for the same seed.
#include <gtest/gtest.h>

#include <cmath>

#include "nav/trackers/simulated_tracker.hpp"

namespace nav::trackers {
namespace {

SimulatedTrackerConfig config(double dropout, std::uint64_t seed) {
  SimulatedTrackerConfig c;
  c.tools = {{1, Trajectory{}, dropout}, {2, Trajectory{{0.1, 0.0, -0.9}, 0.02, -0.5, 0.1, 1.0}, 0.0}};
  c.period_ns = 10 * kNsPerMs;
  c.latency_ns = 25 * kNsPerMs;
  c.position_noise_m = 0.2e-3;
  c.rotation_noise_rad = 0.001;
  c.seed = seed;
  return c;
}

TEST(SimulatedTracker, DeliversEachMeasurementAfterTheLatency) {
  SimulatedTracker tracker(config(0.0, 1));
  std::vector<TrackerSample> samples;
  EXPECT_EQ(tracker.poll(24 * kNsPerMs, samples), 0u);  // frame 0 is due at 25 ms
  EXPECT_EQ(tracker.poll(25 * kNsPerMs, samples), 2u);
  EXPECT_EQ(tracker.poll(55 * kNsPerMs, samples), 6u);  // frames 1..3
  EXPECT_EQ(samples.back().measured_time_ns, 30 * kNsPerMs);
  EXPECT_EQ(samples.back().frame_number, 3u);
  EXPECT_EQ(samples.back().tool_id, 2u);
}

TEST(SimulatedTracker, NoiseAndDropoutsHaveTheConfiguredStatistics) {
  SimulatedTracker tracker(config(0.1, 2));
  std::vector<TrackerSample> samples;
  tracker.poll(100 * kNsPerSecond, samples);
  double sum_squares = 0.0, rotation_squares = 0.0;
  std::size_t poses = 0, dropped = 0, tool_one = 0;
  for (const TrackerSample& sample : samples) {
    if (sample.tool_id == 1) ++tool_one;
    if (sample.state == ToolState::missing) {
      ++dropped;
      continue;
    }
    const TrackerSample truth = tracker.truth(sample.tool_id - 1, sample.measured_time_ns);
    for (int k = 0; k < 3; ++k) sum_squares += std::pow(sample.position_m[k] - truth.position_m[k], 2);
    double dot = 0.0;
    for (int k = 0; k < 4; ++k) dot += sample.orientation_wxyz[k] * truth.orientation_wxyz[k];
    rotation_squares += std::pow(2.0 * std::acos(std::min(1.0, std::abs(dot))), 2);
    ++poses;
  }
  const double position_sigma_m = std::sqrt(sum_squares / (3.0 * static_cast<double>(poses)));
  const double rotation_rms_rad = std::sqrt(rotation_squares / static_cast<double>(poses));
  EXPECT_NEAR(position_sigma_m, 0.2e-3, 0.01e-3);
  EXPECT_NEAR(rotation_rms_rad, std::sqrt(3.0) * 0.001, 0.0001);  // 3 axes of 1 mrad
  EXPECT_NEAR(static_cast<double>(dropped) / static_cast<double>(tool_one), 0.1, 0.01);
}

TEST(SimulatedTracker, SameSeedSameSamples) {
  SimulatedTracker a(config(0.2, 3)), b(config(0.2, 3)), c(config(0.2, 4));
  std::vector<TrackerSample> sa, sb, sc;
  a.poll(kNsPerSecond, sa);
  b.poll(kNsPerSecond, sb);
  c.poll(kNsPerSecond, sc);
  ASSERT_EQ(sa.size(), sb.size());
  for (std::size_t i = 0; i < sa.size(); ++i) {
    EXPECT_EQ(sa[i].position_m, sb[i].position_m);
    EXPECT_EQ(sa[i].state, sb[i].state);
  }
  EXPECT_NE(sa[10].position_m, sc[10].position_m);
}

}  // namespace
}  // namespace nav::trackers
