#include "nav/fusion/breathing_predictor.hpp"

#include <Eigen/Cholesky>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <utility>

namespace nav {
namespace {

Error predictor_option_error(const char* field, const std::string& message) {
  return Error{.message = message, .field = std::string("breathing_predictor.") + field};
}

/// d/dx of a cos(x) + b sin(x), given cos(x) and sin(x).
double harmonic_derivative(double a, double b, double c, double s) noexcept { return b * c - a * s; }

}  // namespace

Result<BreathingPredictor> BreathingPredictor::create(const BreathingPredictorOptions& options) {
  if (options.history_capacity < 4 * static_cast<std::size_t>(kCoefficients))
    return predictor_option_error("history_capacity",
                                  "must hold at least " + std::to_string(4 * kCoefficients) + " samples");
  if (options.min_period_ns <= 0) return predictor_option_error("min_period_ns", "must be positive");
  if (options.max_period_ns <= options.min_period_ns)
    return predictor_option_error("max_period_ns", "must be longer than min_period_ns");
  if (options.fit_window_ns < options.max_period_ns)
    return predictor_option_error("fit_window_ns",
                                  "must cover at least max_period_ns, so that every period can be fitted");
  if (!(options.hysteresis_m >= 0.0)) return predictor_option_error("hysteresis_m", "must not be negative");
  if (options.max_age_ns <= 0) return predictor_option_error("max_age_ns", "must be positive");
  if (!options.axis.allFinite() || !(options.axis.norm() > 0.0))
    return predictor_option_error("axis", "must be a finite non-zero vector");
  BreathingPredictorOptions normalised = options;
  normalised.axis.normalize();
  return BreathingPredictor(normalised);
}

BreathingPredictor::BreathingPredictor(const BreathingPredictorOptions& options)
    : options_(options), samples_(options.history_capacity) {}

HealthFlags BreathingPredictor::push_position(TimeNs time_ns, const Eigen::Vector3d& position_m) noexcept {
  return push(time_ns, options_.axis.dot(position_m));
}

HealthFlags BreathingPredictor::push(TimeNs time_ns, double displacement_m) noexcept {
  HealthFlags flags;
  if (!std::isfinite(displacement_m)) {
    flags.raise(HealthFlag::bad_sample);
    return flags;
  }
  const Sample sample{time_ns, displacement_m};
  if (samples_.empty()) {
    level_m_ = displacement_m;
  } else {
    const Sample previous = samples_.newest();
    if (time_ns <= previous.time_ns && ++backward_run_ < kBackwardRunRestarts) {
      flags.raise(HealthFlag::clock_went_backwards);
      return flags;
    }
    if (time_ns <= previous.time_ns) {
      // The clock really stepped back: restart the history, keep the period (it is still right).
      samples_.clear();
      armed_ = false;
      have_crossing_ = false;
      fitted_ = false;
      level_m_ = displacement_m;
    } else {
      detect_crossing(previous, sample);
    }
  }
  backward_run_ = 0;
  samples_.push(sample);
  refit();
  return flags;
}

void BreathingPredictor::detect_crossing(const Sample& previous, const Sample& sample) noexcept {
  if (sample.displacement_m < level_m_ - options_.hysteresis_m) {
    armed_ = true;
    return;
  }
  if (!armed_ || previous.displacement_m >= level_m_ || sample.displacement_m < level_m_) return;
  // An upward crossing of the level, timed by linear interpolation between the two samples.
  const double fraction = (level_m_ - previous.displacement_m) / (sample.displacement_m - previous.displacement_m);
  const TimeNs crossing_ns =
      previous.time_ns + std::llround(fraction * static_cast<double>(sample.time_ns - previous.time_ns));
  armed_ = false;
  if (have_crossing_) {
    const TimeNs interval_ns = crossing_ns - last_crossing_ns_;
    if (interval_ns < options_.min_period_ns) return;  // noise: keep the earlier crossing
    if (interval_ns <= options_.max_period_ns) {
      intervals_ns_[next_interval_] = interval_ns;
      next_interval_ = (next_interval_ + 1) % kIntervals;
      if (interval_count_ < kIntervals) ++interval_count_;
      update_period();
    }
  }
  have_crossing_ = true;
  last_crossing_ns_ = crossing_ns;
}

void BreathingPredictor::update_period() noexcept {
  std::array<TimeNs, kIntervals> sorted = intervals_ns_;
  for (std::size_t i = 1; i < interval_count_; ++i)  // insertion sort of the few kept intervals
    for (std::size_t j = i; j > 0 && sorted[j - 1] > sorted[j]; --j) std::swap(sorted[j - 1], sorted[j]);
  const std::size_t middle = interval_count_ / 2;
  const double median_s = interval_count_ % 2 == 1
                              ? seconds_of(sorted[middle])
                              : 0.5 * (seconds_of(sorted[middle - 1]) + seconds_of(sorted[middle]));
  const double crossings_rad_s = 2.0 * std::numbers::pi / median_s;
  // The refined frequency stands while it agrees with the crossings; otherwise (first period,
  // a change of breathing, a diverged refinement) the crossings' estimate takes over.
  if (std::abs(omega_rad_s_ - crossings_rad_s) > kCrossingAgreement * crossings_rad_s) omega_rad_s_ = crossings_rad_s;
}

void BreathingPredictor::refit() noexcept {
  // Least squares over the window of the two-harmonic model at omega_, plus one Gauss-Newton
  // step on omega_ itself (its column is the model's derivative along omega at the previous
  // fit), so the frequency is refined by every sample rather than by crossing times alone.
  const TimeNs newest_ns = samples_.newest().time_ns;
  using Unknowns = Eigen::Matrix<double, kCoefficients + 1, 1>;
  using Normal = Eigen::Matrix<double, kCoefficients + 1, kCoefficients + 1>;
  Normal normal = Normal::Zero();
  Unknowns right = Unknowns::Zero();
  Unknowns basis;
  const Coefficients& a = coefficients_;
  const bool refine = fitted_;
  double sum_m = 0.0;
  std::size_t fitted_samples = 0;
  TimeNs first_ns = newest_ns;
  for (std::size_t i = 0; i < samples_.size(); ++i) {  // oldest first: a fixed summation order
    const Sample& sample = samples_.at(i);
    if (newest_ns - sample.time_ns > options_.fit_window_ns) continue;
    if (fitted_samples == 0) first_ns = sample.time_ns;
    ++fitted_samples;
    sum_m += sample.displacement_m;
    const double tau_s = seconds_of(sample.time_ns - newest_ns);
    const double c = std::cos(omega_rad_s_ * tau_s);
    const double s = std::sin(omega_rad_s_ * tau_s);
    const double c2 = 2.0 * c * c - 1.0;
    const double s2 = 2.0 * s * c;
    const double slope = harmonic_derivative(a[1], a[2], c, s) + 2.0 * harmonic_derivative(a[3], a[4], c2, s2);
    const double d_omega = refine ? tau_s * slope : 0.0;  // d(model)/d(omega) at this sample
    basis << 1.0, c, s, c2, s2, d_omega;
    normal.noalias() += basis * basis.transpose();
    right.noalias() += sample.displacement_m * basis;
  }
  if (!refine) normal(kCoefficients, kCoefficients) = 1.0;  // no frequency step without a previous fit
  const double window_mean_m = sum_m / static_cast<double>(fitted_samples);
  fitted_ = false;
  const bool enough = omega_rad_s_ > 0.0 && fitted_samples >= 4 * static_cast<std::size_t>(kCoefficients) &&
                      omega_rad_s_ * seconds_of(newest_ns - first_ns) >= 2.0 * std::numbers::pi;
  if (enough) {
    const Eigen::LDLT<Normal> factor(normal);
    const Unknowns solution = factor.solve(right);
    if (factor.info() == Eigen::Success && solution.allFinite()) {
      coefficients_ = solution.head<kCoefficients>();
      const double max_step = kMaxFrequencyStep * omega_rad_s_;
      omega_rad_s_ += std::clamp(solution[kCoefficients], -max_step, max_step);
      fitted_ = true;
    }
  }
  level_m_ = fitted_ ? coefficients_[0] : window_mean_m;
}

BreathingEstimate BreathingPredictor::predict(TimeNs now_ns, TimeNs horizon_ns) const noexcept {
  BreathingEstimate estimate;
  if (samples_.empty()) {
    estimate.flags.raise(HealthFlag::missing_input);
    return estimate;
  }
  const Sample& newest = samples_.newest();
  if (now_ns - newest.time_ns > options_.max_age_ns) estimate.flags.raise(HealthFlag::stale_input);
  if (omega_rad_s_ > 0.0) estimate.period_s = 2.0 * std::numbers::pi / omega_rad_s_;
  if (!fitted_) {
    estimate.displacement_m = newest.displacement_m;
    estimate.flags.raise(HealthFlag::missing_input);
    return estimate;
  }
  const double angle_rad = omega_rad_s_ * seconds_of(now_ns + horizon_ns - newest.time_ns);
  const double c = std::cos(angle_rad);
  const double s = std::sin(angle_rad);
  Coefficients basis;
  basis << 1.0, c, s, 2.0 * c * c - 1.0, 2.0 * s * c;
  estimate.displacement_m = basis.dot(coefficients_);
  estimate.amplitude_m = std::hypot(coefficients_[1], coefficients_[2]);
  // a cos(x) + b sin(x) = A cos(x - psi), psi = atan2(b, a): phase 0 at the fundamental's peak.
  const double two_pi = 2.0 * std::numbers::pi;
  double phase_rad = std::fmod(angle_rad - std::atan2(coefficients_[2], coefficients_[1]), two_pi);
  if (phase_rad < 0.0) phase_rad += two_pi;
  estimate.phase_rad = phase_rad < two_pi ? phase_rad : 0.0;
  estimate.ready = true;
  return estimate;
}

}  // namespace nav
