// navtool evaluate's comparison (evaluation.hpp) against known errors: a truth moving at a
// constant velocity, outputs offset from it by set distances.
#include <gtest/gtest.h>

#include <cmath>

#include "nav/station/evaluation.hpp"

namespace nav::station {
namespace {

constexpr TimeNs kOriginNs = 5 * kNsPerSecond;  // the truth's first sample on the host's clock
constexpr TimeNs kStepNs = 10 * kNsPerMs;       // the truth's rate (the tissue step)
constexpr double kSpeedMPerS = 0.01;            // the tumour moves along x
constexpr TimeNs kHorizonNs = 50 * kNsPerMs;

dds::Vector3 tumour_at(TimeNs t) { return {kSpeedMPerS * 1e-9 * static_cast<double>(t - kOriginNs), 0.02, -0.01}; }
dds::Vector3 tip_at(TimeNs t) { return {0.0, 0.1 - kSpeedMPerS * 1e-9 * static_cast<double>(t - kOriginNs), 0.0}; }

/// 4 s of truth at the tissue rate, and its predictions every 10 ms half-way between truth
/// samples (interpolated): now 1 mm off along z, ahead 2 mm off along y (against the truth at
/// t + horizon), the needle tip 3 mm off along x.
EvaluationInput four_seconds() {
  EvaluationInput input;
  for (TimeNs t = kOriginNs; t <= kOriginNs + 4 * kNsPerSecond; t += kStepNs)
    input.truths.push_back({t, 0, tumour_at(t), tip_at(t)});
  for (TimeNs t = kOriginNs + kStepNs / 2; t < kOriginNs + 4 * kNsPerSecond - kHorizonNs; t += kStepNs) {
    dds::TargetPrediction now;
    now.source_time_ns = t;
    now.position_m = tumour_at(t);
    now.position_m[2] += 0.001;
    now.receive_time_ns = t + 2 * kNsPerMs;                      // 2 ms from the station's tick to the reader
    now.model_rung = t >= kOriginNs + 3 * kNsPerSecond ? 1 : 0;  // the ladder's rung 1 for the last second
    dds::TargetPrediction ahead = now;
    ahead.receive_time_ns = 0;  // not stamped (e.g. written by hand): not timed
    ahead.horizon_ns = kHorizonNs;
    ahead.position_m = tumour_at(t + kHorizonNs);
    ahead.position_m[1] += 0.002;
    input.predictions.push_back(ahead);  // any order
    input.predictions.push_back(now);
    dds::Vector3 tip = tip_at(t);
    tip[0] -= 0.003;
    input.needle_tips.push_back({t, tip});
  }
  return input;
}

TEST(Evaluation, RmsErrorsAreTheOffsetsAgainstTheInterpolatedTruth) {
  const Evaluation e = evaluate(four_seconds(), 0);
  EXPECT_NEAR(e.tumour_now_rms_m, 0.001, 1e-12);
  EXPECT_NEAR(e.tumour_ahead_rms_m, 0.002, 1e-12);
  EXPECT_NEAR(e.needle_tip_rms_m, 0.003, 1e-12);
  EXPECT_EQ(e.horizon_ns, kHorizonNs);
  EXPECT_EQ(e.tumour_now_count, e.tumour_ahead_count);
  EXPECT_EQ(e.tumour_now_count, e.needle_tip_count);
  EXPECT_EQ(e.tumour_now_count, 395);
  EXPECT_EQ(e.without_truth, 0);
  ASSERT_EQ(e.series.size(), 3u);
  EXPECT_NEAR(e.series[0].y.front(), 1.0, 1e-9);     // millimetres
  EXPECT_NEAR(e.series[0].x.front(), 0.005, 1e-12);  // seconds from the first truth
  EXPECT_EQ(e.tick_to_reader.count, 395);
  ASSERT_EQ(e.predictions_by_rung.size(), 2u);
  EXPECT_EQ(e.predictions_by_rung.at(0), 300);
  EXPECT_EQ(e.predictions_by_rung.at(1), 95);
  EXPECT_NE(format_evaluation(e, 0).find("by liver rung: 0: 300; 1: 95;"), std::string::npos);
  EXPECT_NE(evaluation_json(e).find("\"predictions_by_rung\": {\"0\": 300, \"1\": 95}"), std::string::npos);
  EXPECT_DOUBLE_EQ(e.tick_to_reader.median_us, 2000.0);
  EXPECT_DOUBLE_EQ(e.tick_to_reader.max_us, 2000.0);
}

TEST(Evaluation, OutputsBeforeTheSettleTimeOrBeyondTheTruthAreNotCompared) {
  EvaluationInput input = four_seconds();
  dds::TargetPrediction late;
  late.source_time_ns = kOriginNs + 10 * kNsPerSecond;  // after the truth ended
  input.predictions.push_back(late);
  const Evaluation e = evaluate(input, 1 * kNsPerSecond);
  EXPECT_EQ(e.tumour_now_count, 295);  // from 1.005 s
  EXPECT_EQ(e.without_truth, 3 * 100 + 1);
  EXPECT_NEAR(e.tumour_now_rms_m, 0.001, 1e-12);
}

TEST(Evaluation, AGapInTheTruthIsNotBridged) {
  EvaluationInput input = four_seconds();
  // 200 ms of truth lost (more than kMaxTruthGapNs): the outputs inside the gap have no truth.
  std::erase_if(input.truths, [](const dds::GroundTruth& t) {
    return t.source_time_ns > kOriginNs + 2 * kNsPerSecond &&
           t.source_time_ns < kOriginNs + 2 * kNsPerSecond + 200 * kNsPerMs;
  });
  const Evaluation e = evaluate(input, 0);
  EXPECT_EQ(e.tumour_now_count, 395 - 20);
  EXPECT_NEAR(e.tumour_now_rms_m, 0.001, 1e-12);
}

TEST(Evaluation, WithoutTruthNothingIsComparedAndTheReportSaysSoButTheLatencyIsTimed) {
  EvaluationInput input = four_seconds();
  input.truths.clear();
  const Evaluation e = evaluate(input, 0);
  EXPECT_EQ(e.tumour_now_count, 0);
  EXPECT_EQ(e.without_truth, static_cast<std::int64_t>(input.predictions.size() + input.needle_tips.size()));
  EXPECT_NE(format_evaluation(e, 0).find("outputs without a truth to compare: " + std::to_string(e.without_truth)),
            std::string::npos);
  EXPECT_EQ(e.tick_to_reader.count, 395);  // the latency to the reader needs no truth
  EXPECT_EQ(e.predictions_by_rung.at(0) + e.predictions_by_rung.at(1), 395);
}

}  // namespace
}  // namespace nav::station
