#include "nav/calibration/temporal_calibration.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>

namespace nav::calibration {
namespace {

/// Linear interpolation of `signal` on the grid start + i * step, i < count.
std::vector<double> resample(const TimedSignal& signal, double start_s, double step_s, std::size_t count) {
  std::vector<double> values(count);
  std::size_t k = 0;
  for (std::size_t i = 0; i < count; ++i) {
    const double t = start_s + static_cast<double>(i) * step_s;
    while (k + 2 < signal.times_s.size() && signal.times_s[k + 1] < t) ++k;
    const double t0 = signal.times_s[k], t1 = signal.times_s[k + 1];
    const double alpha = std::clamp((t - t0) / (t1 - t0), 0.0, 1.0);
    values[i] = (1.0 - alpha) * signal.values[k] + alpha * signal.values[k + 1];
  }
  return values;
}

/// Pearson correlation of fixed[i] and moving[i + shift] over i in [from, to).
double correlation(const std::vector<double>& fixed, const std::vector<double>& moving, std::ptrdiff_t shift,
                   std::size_t from, std::size_t to) {
  double sum_f = 0, sum_m = 0, sum_ff = 0, sum_mm = 0, sum_fm = 0;
  std::size_t n = 0;
  for (std::size_t i = from; i < to; ++i) {
    const std::ptrdiff_t j = static_cast<std::ptrdiff_t>(i) + shift;
    if (j < 0 || j >= static_cast<std::ptrdiff_t>(moving.size())) continue;
    const double f = fixed[i], m = moving[static_cast<std::size_t>(j)];
    sum_f += f, sum_m += m, sum_ff += f * f, sum_mm += m * m, sum_fm += f * m;
    ++n;
  }
  if (n < 2) return 0.0;
  const double count = static_cast<double>(n);
  const double variance = (sum_ff - sum_f * sum_f / count) * (sum_mm - sum_m * sum_m / count);
  return variance > 0.0 ? (sum_fm - sum_f * sum_m / count) / std::sqrt(variance) : 0.0;
}

struct Peak {
  double lag_s = 0.0;
  double correlation = 0.0;
  bool at_edge = false;
};

/// Scans the lags for the fixed grid stretch [from, to), maximising sign * r, or |r| when
/// sign is 0.
Peak scan(const std::vector<double>& fixed, const std::vector<double>& moving, std::ptrdiff_t offset, std::size_t from,
          std::size_t to, double sign, const TemporalOptions& options) {
  const auto window = static_cast<std::ptrdiff_t>(std::llround(options.max_lag_s / options.step_s));
  std::vector<double> scores;
  for (std::ptrdiff_t lag = -window; lag <= window; ++lag) {
    const double r = correlation(fixed, moving, offset + lag, from, to);
    scores.push_back(sign == 0.0 ? std::abs(r) : sign * r);
  }
  const auto best = static_cast<std::size_t>(std::max_element(scores.begin(), scores.end()) - scores.begin());
  Peak peak;
  peak.correlation = correlation(fixed, moving, offset + static_cast<std::ptrdiff_t>(best) - window, from, to);
  peak.at_edge = best < 2 || best + 2 >= scores.size();
  double refine = 0.0;
  if (!peak.at_edge) {
    const double left = scores[best - 1], centre = scores[best], right = scores[best + 1];
    const double curvature = left - 2.0 * centre + right;
    if (curvature < 0.0) refine = 0.5 * (left - right) / curvature;
  }
  peak.lag_s = (static_cast<double>(best) - static_cast<double>(window) + refine) * options.step_s;
  return peak;
}

std::optional<Error> check(const TimedSignal& signal, const char* name) {
  if (signal.times_s.size() != signal.values.size())
    return Error{.message = "times and values differ in number", .field = name};
  for (std::size_t i = 1; i < signal.times_s.size(); ++i) {
    if (!(signal.times_s[i] > signal.times_s[i - 1]))
      return Error{.message = "time stamps must increase", .field = name};
  }
  for (const double value : signal.values) {
    if (!std::isfinite(value)) return Error{.message = "a value is not finite", .field = name};
  }
  const auto [low, high] = std::minmax_element(signal.values.begin(), signal.values.end());
  if (!signal.values.empty() && *low == *high)
    return Error{.message = "the signal is flat (no motion to correlate)", .field = name};
  return std::nullopt;
}

}  // namespace

Result<LagEstimate> estimate_lag(const TimedSignal& fixed, const TimedSignal& moving, const TemporalOptions& options) {
  if (auto problem = check(fixed, "fixed")) return *problem;
  if (auto problem = check(moving, "moving")) return *problem;
  if (fixed.times_s.size() < options.min_samples || moving.times_s.size() < options.min_samples) {
    return Error{.message = "too few samples for a temporal calibration", .field = "signals"};
  }
  // The fixed grid covers the fixed signal's span; the moving one its own, extended by the
  // window so that every scanned lag finds samples.
  const double step = options.step_s;
  const double fixed_start = fixed.times_s.front();
  const auto fixed_count = static_cast<std::size_t>((fixed.times_s.back() - fixed_start) / step) + 1;
  const double moving_start = moving.times_s.front();
  const auto moving_count = static_cast<std::size_t>((moving.times_s.back() - moving_start) / step) + 1;
  const std::vector<double> fixed_grid = resample(fixed, fixed_start, step, fixed_count);
  const std::vector<double> moving_grid = resample(moving, moving_start, step, moving_count);
  const auto offset = static_cast<std::ptrdiff_t>(std::llround((fixed_start - moving_start) / step));
  // Correlate over the fixed grid's stretch that the moving signal covers.
  const double overlap_start = std::max(fixed_start, moving_start),
               overlap_end = std::min(fixed.times_s.back(), moving.times_s.back());
  if (overlap_end - overlap_start < 4.0 * options.max_lag_s) {
    return Error{.message = "the signals overlap for less than four search windows", .field = "signals"};
  }
  const auto from = static_cast<std::size_t>((overlap_start - fixed_start) / step);
  const auto to = std::min(fixed_count, static_cast<std::size_t>((overlap_end - fixed_start) / step) + 1);

  const Peak whole = scan(fixed_grid, moving_grid, offset, from, to, options.allow_inverted ? 0.0 : 1.0, options);
  if (whole.at_edge || std::abs(whole.correlation) < options.min_peak_correlation) {
    std::ostringstream message;
    message << "the lag lies beyond the search window of +-" << options.max_lag_s << " s (best correlation in it "
            << whole.correlation << (whole.at_edge ? ", at its edge)" : ")");
    return Error{.message = message.str(), .field = "max_lag_s"};
  }
  LagEstimate estimate;
  estimate.lag_s = whole.lag_s;
  estimate.correlation = whole.correlation;
  // The stretches keep the whole recording's sign, so that a periodic motion's opposite
  // phase cannot pass for a peak.
  const double sign = whole.correlation < 0.0 ? -1.0 : 1.0;
  std::vector<double> lags;
  for (std::size_t s = 0; s < options.segments; ++s) {
    const Peak part = scan(fixed_grid, moving_grid, offset, from + s * (to - from) / options.segments,
                           from + (s + 1) * (to - from) / options.segments, sign, options);
    if (!part.at_edge && std::abs(part.correlation) >= options.min_peak_correlation) lags.push_back(part.lag_s);
  }
  estimate.segments_used = lags.size();
  if (lags.size() >= 2) {
    double mean = 0.0, spread = 0.0;
    for (const double lag : lags) mean += lag / static_cast<double>(lags.size());
    for (const double lag : lags) spread += (lag - mean) * (lag - mean) / static_cast<double>(lags.size() - 1);
    estimate.uncertainty_s = std::sqrt(spread / static_cast<double>(lags.size()));
  } else {
    estimate.uncertainty_s = options.max_lag_s;  // no independent stretch agreed: as wide as the window
  }
  return estimate;
}

}  // namespace nav::calibration
