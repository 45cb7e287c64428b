#pragma once
// Breathing from a tracked marker: its displacement along the breathing axis gives a first
// period (median of level-crossing intervals); a least-squares fit of a two-harmonic periodic
// model over a fixed window, with one Gauss-Newton step on the frequency per sample, refines
// it and gives phase, amplitude and the displacement predicted ahead, e.g. at the time a
// display will show the frame.
#include <Eigen/Core>

#include <array>
#include <cstddef>

#include "nav/core/clock.hpp"
#include "nav/core/error.hpp"
#include "nav/core/health.hpp"
#include "nav/fusion/history_ring.hpp"

namespace nav {

/// Window, period range and axis of a BreathingPredictor; checked by BreathingPredictor::create.
struct BreathingPredictorOptions {
  std::size_t history_capacity = 384;       // samples kept, the fit's fixed cost: cover the window at the marker rate
  TimeNs fit_window_ns = 8 * kNsPerSecond;  // samples older than this (before the newest) are not fitted
  TimeNs min_period_ns = 1 * kNsPerSecond;  // shorter crossing intervals are noise
  TimeNs max_period_ns = 8 * kNsPerSecond;  // longer ones are not periods (no more than fit_window_ns)
  double hysteresis_m = 0.5e-3;             // the signal must fall this far below the level to re-arm a crossing
  TimeNs max_age_ns = 500 * kNsPerMs;       // newest sample older than this at a query: stale_input
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();  // breathing axis for push_position (normalised at create)
};

/// What the predictor says about the breathing at a target time.
struct BreathingEstimate {
  double displacement_m = 0.0;  // predicted displacement along the axis at the target time
  double phase_rad = 0.0;       // in [0, 2 pi); 0 at the fundamental's maximum displacement
  double amplitude_m = 0.0;     // amplitude of the fundamental
  double period_s = 0.0;        // current period estimate (0 before the first one)
  bool ready = false;           // a period is known and the model is fitted
  HealthFlags flags;            // missing_input before ready, stale_input when the marker is late
};

/// Tracks a 1-D respiratory signal and predicts it ahead. create() allocates; push(),
/// push_position() and predict() never allocate, throw or make system calls, and cost at
/// most a fixed amount (one fit over history_capacity samples per push).
class BreathingPredictor {
 public:
  /// A predictor with storage for `options.history_capacity` samples, or an Error naming the bad field.
  static Result<BreathingPredictor> create(const BreathingPredictorOptions& options);

  /// Adds a displacement sample and refits. Returns bad_sample (non-finite) or
  /// clock_went_backwards (time not after the newest) when the sample is dropped; the
  /// kBackwardRunRestarts-th backward sample in a row restarts the history from it instead
  /// (the period estimate is kept), so a clock step never locks the predictor out.
  HealthFlags push(TimeNs time_ns, double displacement_m) noexcept;
  /// Adds a marker position, projected on the configured axis.
  HealthFlags push_position(TimeNs time_ns, const Eigen::Vector3d& position_m) noexcept;

  /// The breathing at `now_ns + horizon_ns`. Before the model is ready, holds the newest
  /// displacement (0 if none) with missing_input.
  BreathingEstimate predict(TimeNs now_ns, TimeNs horizon_ns) const noexcept;

  static constexpr int kHarmonics = 2;
  static constexpr int kCoefficients = 1 + 2 * kHarmonics;
  static constexpr std::size_t kIntervals = 5;        // crossing intervals in the period's median
  static constexpr double kMaxFrequencyStep = 0.01;   // relative bound of one Gauss-Newton step on the frequency
  static constexpr double kCrossingAgreement = 0.05;  // refined frequency kept while within 5 % of the crossings'
  static constexpr int kBackwardRunRestarts = 3;      // backward samples in a row that restart the history

 private:
  struct Sample {
    TimeNs time_ns;
    double displacement_m;
  };
  using Coefficients = Eigen::Matrix<double, kCoefficients, 1>;

  explicit BreathingPredictor(const BreathingPredictorOptions& options);
  void detect_crossing(const Sample& previous, const Sample& sample) noexcept;
  void update_period() noexcept;
  void refit() noexcept;

  BreathingPredictorOptions options_;
  HistoryRing<Sample> samples_;
  double level_m_ = 0.0;  // the crossing level: the fitted mean, or the window mean before a fit
  bool armed_ = false;    // the signal went below level - hysteresis since the last crossing
  bool have_crossing_ = false;
  TimeNs last_crossing_ns_ = 0;
  std::array<TimeNs, kIntervals> intervals_ns_{};  // ring of recent crossing intervals
  std::size_t interval_count_ = 0;
  std::size_t next_interval_ = 0;
  double omega_rad_s_ = 0.0;  // fitted breathing frequency; 0 until a period is known
  bool fitted_ = false;
  int backward_run_ = 0;                              // consecutive samples behind the newest one
  Coefficients coefficients_ = Coefficients::Zero();  // [mean, cos k, sin k ...] at time relative to the newest sample
};

}  // namespace nav
