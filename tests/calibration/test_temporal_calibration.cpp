// Temporal calibration: the lag against synthetic truth (<= 1 ms) with noise, jitter and
// different rates, the search-window and degenerate errors, the line signal against a drawn
// line (the real water-tank recordings: test_temporal_calibration_navtool.cpp).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "nav/calibration/temporal_calibration.hpp"
#include "nav/calibration/temporal_calibration_signals.hpp"

namespace nav::calibration {
namespace {

/// A probe's up-and-down motion (mm): a few incommensurate sines.
double motion_mm(double t) {
  return 10.0 * std::sin(2.0 * M_PI * 0.45 * t) + 4.0 * std::sin(2.0 * M_PI * 1.1 * t + 1.0) +
         2.0 * std::sin(2.0 * M_PI * 0.17 * t + 0.3);
}

/// `motion_mm` seen by a device `lag_s` late, at `rate_hz` with time-stamp jitter and noise,
/// scaled by `gain` (negative: the signal moves the other way).
TimedSignal device(double lag_s, double rate_hz, double gain, double duration_s, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> jitter(0.0, 0.1 / rate_hz), noise(0.0, 0.2);
  TimedSignal signal;
  for (double t = 0.0; t < duration_s; t += 1.0 / rate_hz) {
    const double stamp = t + jitter(rng);
    if (!signal.times_s.empty() && stamp <= signal.times_s.back()) continue;
    signal.times_s.push_back(stamp);
    signal.values.push_back(gain * motion_mm(stamp - lag_s) + noise(rng));
  }
  return signal;
}

TEST(TemporalCalibration, SyntheticLagWithinOneMillisecond) {
  for (const double lag_s : {0.0374, -0.1216, 0.2503}) {
    const TimedSignal tracker = device(0.0, 60.0, 1.0, 20.0, 1);
    const TimedSignal video = device(lag_s, 25.0, -3.5, 20.0, 2);  // pixels, inverted
    const auto estimate = estimate_lag(tracker, video);
    ASSERT_TRUE(estimate.ok()) << estimate.error().describe();
    std::printf("true lag %.1f ms: estimate %.3f ms +- %.3f ms (r = %.3f)\n", 1e3 * lag_s, 1e3 * estimate.value().lag_s,
                1e3 * estimate.value().uncertainty_s, estimate.value().correlation);
    EXPECT_NEAR(estimate.value().lag_s, lag_s, 1e-3);
    EXPECT_LT(estimate.value().uncertainty_s, 1e-3);
    EXPECT_LT(estimate.value().correlation, -0.95);
  }
}

TEST(TemporalCalibration, LagBeyondTheWindowIsAnError) {
  const TimedSignal tracker = device(0.0, 60.0, 1.0, 20.0, 3);
  const TimedSignal video = device(0.8, 25.0, 1.0, 20.0, 4);
  const auto estimate = estimate_lag(tracker, video, {.max_lag_s = 0.5});
  ASSERT_FALSE(estimate.ok()) << estimate.value().lag_s << " r " << estimate.value().correlation;
  EXPECT_NE(estimate.error().message.find("beyond the search window"), std::string::npos);
  EXPECT_EQ(estimate.error().field, "max_lag_s");
  // Without inversion the peak sits at the window's edge.
  const auto upright = estimate_lag(tracker, video, {.max_lag_s = 0.5, .allow_inverted = false});
  ASSERT_FALSE(upright.ok());
  EXPECT_NE(upright.error().message.find("at its edge"), std::string::npos);
  const auto wider = estimate_lag(tracker, video, {.max_lag_s = 1.0});
  ASSERT_TRUE(wider.ok());
  EXPECT_NEAR(wider.value().lag_s, 0.8, 1e-3);
}

TEST(TemporalCalibration, DegenerateSignalsAreErrors) {
  const TimedSignal tracker = device(0.0, 60.0, 1.0, 20.0, 5);
  TimedSignal short_signal = device(0.0, 60.0, 1.0, 0.2, 6);
  EXPECT_NE(estimate_lag(tracker, short_signal).error().message.find("too few"), std::string::npos);
  TimedSignal flat = tracker;
  for (double& value : flat.values) value = 1.0;
  EXPECT_NE(estimate_lag(tracker, flat).error().message.find("flat"), std::string::npos);
  TimedSignal backwards = tracker;
  std::swap(backwards.times_s[3], backwards.times_s[4]);
  EXPECT_EQ(estimate_lag(tracker, backwards).error().field, "moving");
}

TEST(TemporalCalibration, LineRowOfADrawnLine) {
  const int width = 200, height = 120;
  std::vector<std::uint8_t> image(width * height, 5);
  for (int x = 20; x < 180; ++x) {
    const double row = 40.0 + 0.25 * x;  // two rows thick, brightest on the line
    for (int y = 0; y < height; ++y) {
      const double distance = std::abs(y - row);
      if (distance < 1.5) image[y * width + x] = static_cast<std::uint8_t>(250 - 80 * distance);
    }
  }
  const auto row = bright_line_row_px(image.data(), width, height, {0, 0, width, height});
  ASSERT_TRUE(row.has_value());
  EXPECT_NEAR(*row, 40.0 + 0.25 * 99.5, 0.1);
  std::vector<std::uint8_t> blank(width * height, 0);
  EXPECT_FALSE(bright_line_row_px(blank.data(), width, height, {0, 0, width, height}).has_value());
}

}  // namespace
}  // namespace nav::calibration
