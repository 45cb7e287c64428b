#pragma once
// Temporal calibration: the lag of one device's time stamps against another's, from one
// motion seen by both (e.g. a probe moved up and down over a water tank's flat bottom: the
// tracker sees its height, the scanner the bottom line's depth). The lag maximises the
// normalised cross-correlation of the two signals, taken at the sparser one's own samples
// (the video's frames) with the denser one interpolated there, scanned over a search window
// in steps and refined to below a step by a parabola through the peak; its uncertainty is
// the spread of the lags of separate stretches of the recording.
#include <cstddef>
#include <vector>

#include "nav/core/error.hpp"

namespace nav::calibration {

/// A scalar signal sampled at increasing times (seconds, on the device's own time stamps).
struct TimedSignal {
  std::vector<double> times_s;
  std::vector<double> values;
};

/// Settings of estimate_lag.
struct TemporalOptions {
  double max_lag_s = 0.5;             ///< the search window is [-max_lag_s, max_lag_s]
  double step_s = 0.001;              ///< lag scan step
  std::size_t min_samples = 20;       ///< per signal, in the overlap
  std::size_t segments = 4;           ///< stretches for the uncertainty
  bool allow_inverted = true;         ///< accept a negative correlation (a signal moving the other way)
  double min_peak_correlation = 0.9;  ///< a weaker best peak means the lag is not in the window
};

/// The estimated lag: moving(t + lag_s) matches fixed(t), so subtracting lag_s from the
/// moving device's time stamps aligns it with the fixed one.
struct LagEstimate {
  double lag_s = 0.0;
  double uncertainty_s = 0.0;  ///< standard error from the stretches
  double correlation = 0.0;    ///< at the peak, signed
  std::size_t segments_used = 0;
};

/// Estimates the lag of `moving` against `fixed`. Errors: too few samples, an overlap shorter
/// than four windows, flat signals, and no clear peak inside the search window (at its edge
/// or weaker than min_peak_correlation: the lag lies beyond it).
Result<LagEstimate> estimate_lag(const TimedSignal& fixed, const TimedSignal& moving,
                                 const TemporalOptions& options = {});

}  // namespace nav::calibration
