#include "nav/calibration/temporal_calibration.hpp"

#include <algorithm>
#include <cmath>
#include <optional>
#include <sstream>

namespace nav::calibration {
namespace {

/// The value of `signal` at `t_s` by linear interpolation, from `hint` on (moved forward; the
/// times asked for increase); nullopt outside its span.
std::optional<double> value_at(const TimedSignal& signal, double t_s, std::size_t& hint) {
  if (t_s < signal.times_s.front() || t_s > signal.times_s.back()) return std::nullopt;
  while (hint + 2 < signal.times_s.size() && signal.times_s[hint + 1] < t_s) ++hint;
  const double t0 = signal.times_s[hint], t1 = signal.times_s[hint + 1];
  const double alpha = std::clamp((t_s - t0) / (t1 - t0), 0.0, 1.0);
  return (1.0 - alpha) * signal.values[hint] + alpha * signal.values[hint + 1];
}

/// The two signals as the correlation pairs them: the sparser one (fewer samples a second) at
/// its own samples, the denser one interpolated there, so that no value is made up between
/// two samples of the sparse one. A lag pairs fixed(t) with moving(t + lag).
struct Pairing {
  const TimedSignal& sampled;
  const TimedSignal& interpolated;
  double lag_sign;  ///< +1: the sampled one is fixed (interpolated at t + lag); -1: at t - lag
};

/// Pearson correlation at `lag_s` over the sampled signal's samples [from, to).
double correlation(const Pairing& pairing, double lag_s, std::size_t from, std::size_t to) {
  double sum_f = 0, sum_m = 0, sum_ff = 0, sum_mm = 0, sum_fm = 0;
  std::size_t n = 0, hint = 0;
  for (std::size_t i = from; i < to; ++i) {
    const auto other = value_at(pairing.interpolated, pairing.sampled.times_s[i] + pairing.lag_sign * lag_s, hint);
    if (!other) continue;
    const double f = pairing.sampled.values[i], m = *other;
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

/// Scans the lags over the sampled signal's stretch [from, to), maximising sign * r, or |r|
/// when sign is 0.
Peak scan(const Pairing& pairing, std::size_t from, std::size_t to, double sign, const TemporalOptions& options) {
  const auto window = static_cast<std::ptrdiff_t>(std::llround(options.max_lag_s / options.step_s));
  std::vector<double> scores;
  for (std::ptrdiff_t lag = -window; lag <= window; ++lag) {
    const double r = correlation(pairing, static_cast<double>(lag) * options.step_s, from, to);
    scores.push_back(sign == 0.0 ? std::abs(r) : sign * r);
  }
  const auto best = static_cast<std::size_t>(std::max_element(scores.begin(), scores.end()) - scores.begin());
  Peak peak;
  peak.correlation =
      correlation(pairing, static_cast<double>(static_cast<std::ptrdiff_t>(best) - window) * options.step_s, from, to);
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
  const double overlap_start = std::max(fixed.times_s.front(), moving.times_s.front()),
               overlap_end = std::min(fixed.times_s.back(), moving.times_s.back());
  if (overlap_end - overlap_start < 4.0 * options.max_lag_s) {
    return Error{.message = "the signals overlap for less than four search windows", .field = "signals"};
  }
  const auto rate = [](const TimedSignal& s) {
    return static_cast<double>(s.times_s.size()) / (s.times_s.back() - s.times_s.front());
  };
  const bool fixed_sampled = rate(fixed) <= rate(moving);
  const Pairing pairing{fixed_sampled ? fixed : moving, fixed_sampled ? moving : fixed, fixed_sampled ? 1.0 : -1.0};
  // Correlate over the sampled signal's samples inside the overlap.
  const std::vector<double>& times = pairing.sampled.times_s;
  const auto from =
      static_cast<std::size_t>(std::lower_bound(times.begin(), times.end(), overlap_start) - times.begin());
  const auto to = static_cast<std::size_t>(std::upper_bound(times.begin(), times.end(), overlap_end) - times.begin());

  const Peak whole = scan(pairing, from, to, options.allow_inverted ? 0.0 : 1.0, options);
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
    const Peak part = scan(pairing, from + s * (to - from) / options.segments,
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
