#pragma once
// Evaluation of a station from outside: its predictions (nav/target_prediction) and modelled
// needle (nav/needle_state) against a simulated patient's truth (nav/ground_truth), all on
// the host's clock, as navtool evaluate receives them live or reads them from a recording.
// The truth is interpolated linearly between its samples; a prediction stamped t with horizon
// h is compared with the truth at t + h. Report-time code.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "nav/core/clock.hpp"
#include "nav/dds/samples.hpp"
#include "nav/station/error_plot.hpp"
#include "nav/station/station_run.hpp"

namespace nav::station {

/// The modelled needle's tip at a time (the last point of a NeedleState).
struct TimedTip {
  TimeNs time_ns = 0;
  dds::Vector3 tip_m{};
};

/// What an evaluation compares: the station's outputs and the truth, in any order.
struct EvaluationInput {
  std::vector<dds::TargetPrediction> predictions;
  std::vector<TimedTip> needle_tips;
  std::vector<dds::GroundTruth> truths;
};

/// RMS errors (and their curves) of the outputs that have a truth, from settle_ns after the first truth.
struct Evaluation {
  std::int64_t tumour_now_count = 0, tumour_ahead_count = 0, needle_tip_count = 0;
  double tumour_now_rms_m = 0.0, tumour_ahead_rms_m = 0.0, needle_tip_rms_m = 0.0;
  TimeNs horizon_ns = 0;           ///< the predictions ahead's horizon (the newest seen)
  std::int64_t without_truth = 0;  ///< outputs outside the truth's span (or before settle_ns), not compared
  /// From the station's tick (a prediction's source time) to its arrival here (its receive
  /// time), both on this host's monotonic clock, over the predictions that carry one.
  LatencyStatistics tick_to_reader;
  /// The predictions of the tumour now by the liver rung that made them (0: the scene's
  /// reduced rung, 1 ...: the escalation ladder's rungs above it).
  std::map<std::uint32_t, std::int64_t> predictions_by_rung;
  std::vector<PlotSeries> series;  ///< tumour now and ahead, needle tip: error (mm) over time (s from the first truth)
};

/// The truth's linear interpolation between samples further apart than this is refused (a gap).
inline constexpr TimeNs kMaxTruthGapNs = 100 * kNsPerMs;

Evaluation evaluate(EvaluationInput input, TimeNs settle_ns);

/// The printed lines of an evaluation.
std::string format_evaluation(const Evaluation& evaluation, TimeNs settle_ns);

/// The same figures as one JSON object.
std::string evaluation_json(const Evaluation& evaluation);

}  // namespace nav::station
