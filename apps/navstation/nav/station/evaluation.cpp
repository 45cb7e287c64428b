#include "nav/station/evaluation.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>

namespace nav::station {

namespace {

/// The truth (sorted by time) at `time_ns`: tumour (or needle tip), or nothing outside its span or in a gap.
std::optional<dds::Vector3> truth_at(const std::vector<dds::GroundTruth>& truths, TimeNs time_ns, bool needle) {
  const auto after = std::lower_bound(truths.begin(), truths.end(), time_ns,
                                      [](const dds::GroundTruth& t, TimeNs time) { return t.source_time_ns < time; });
  if (after == truths.end()) return std::nullopt;
  if (after->source_time_ns == time_ns) return needle ? after->needle_tip_m : after->tumour_m;
  if (after == truths.begin()) return std::nullopt;
  const dds::GroundTruth& a = *(after - 1);
  const dds::GroundTruth& b = *after;
  if (b.source_time_ns - a.source_time_ns > kMaxTruthGapNs) return std::nullopt;
  const double f =
      static_cast<double>(time_ns - a.source_time_ns) / static_cast<double>(b.source_time_ns - a.source_time_ns);
  const dds::Vector3& pa = needle ? a.needle_tip_m : a.tumour_m;
  const dds::Vector3& pb = needle ? b.needle_tip_m : b.tumour_m;
  return dds::Vector3{pa[0] + f * (pb[0] - pa[0]), pa[1] + f * (pb[1] - pa[1]), pa[2] + f * (pb[2] - pa[2])};
}

double distance_m(const dds::Vector3& a, const dds::Vector3& b) {
  return std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
}

/// Accumulates one error curve and its RMS.
struct ErrorCurve {
  PlotSeries series;
  double sum2 = 0.0;
  std::int64_t count = 0;

  void add(double seconds, double error_m) {
    series.x.push_back(seconds);
    series.y.push_back(1e3 * error_m);
    sum2 += error_m * error_m;
    ++count;
  }
  double rms_m() const { return count > 0 ? std::sqrt(sum2 / static_cast<double>(count)) : 0.0; }
};

}  // namespace

Evaluation evaluate(EvaluationInput input, TimeNs settle_ns) {
  Evaluation e;
  auto& truths = input.truths;
  // Timed and counted with or without a truth (a station on real devices has none).
  std::vector<double> tick_to_reader_us;
  for (const dds::TargetPrediction& p : input.predictions)
    if (p.receive_time_ns > 0)
      tick_to_reader_us.push_back(1e-3 * static_cast<double>(p.receive_time_ns - p.source_time_ns));
  e.tick_to_reader = latency_statistics(std::move(tick_to_reader_us));
  for (const dds::TargetPrediction& p : input.predictions)
    if (p.horizon_ns == 0) ++e.predictions_by_rung[p.model_rung];
  std::sort(truths.begin(), truths.end(),
            [](const dds::GroundTruth& a, const dds::GroundTruth& b) { return a.source_time_ns < b.source_time_ns; });
  if (truths.empty()) {
    e.without_truth = static_cast<std::int64_t>(input.predictions.size() + input.needle_tips.size());
    return e;
  }
  const TimeNs origin_ns = truths.front().source_time_ns;
  const TimeNs from_ns = origin_ns + settle_ns;
  const auto seconds = [origin_ns](TimeNs t) { return 1e-9 * static_cast<double>(t - origin_ns); };
  ErrorCurve now{{"tumour now", "#1f77b4", false, {}, {}}}, ahead{{"tumour ahead", "#2ca02c", false, {}, {}}},
      tip{{"needle tip", "#d62728", true, {}, {}}};
  std::sort(input.predictions.begin(), input.predictions.end(),
            [](const dds::TargetPrediction& a, const dds::TargetPrediction& b) {
              return a.source_time_ns < b.source_time_ns;
            });
  for (const dds::TargetPrediction& p : input.predictions) {
    const TimeNs at_ns = p.source_time_ns + p.horizon_ns;
    const std::optional<dds::Vector3> truth =
        p.source_time_ns >= from_ns ? truth_at(truths, at_ns, false) : std::nullopt;
    if (!truth) {
      ++e.without_truth;
      continue;
    }
    (p.horizon_ns == 0 ? now : ahead).add(seconds(p.source_time_ns), distance_m(p.position_m, *truth));
    if (p.horizon_ns != 0) e.horizon_ns = p.horizon_ns;
  }
  std::sort(input.needle_tips.begin(), input.needle_tips.end(),
            [](const TimedTip& a, const TimedTip& b) { return a.time_ns < b.time_ns; });
  for (const TimedTip& t : input.needle_tips) {
    const std::optional<dds::Vector3> truth = t.time_ns >= from_ns ? truth_at(truths, t.time_ns, true) : std::nullopt;
    if (!truth) {
      ++e.without_truth;
      continue;
    }
    tip.add(seconds(t.time_ns), distance_m(t.tip_m, *truth));
  }
  e.tumour_now_count = now.count;
  e.tumour_ahead_count = ahead.count;
  e.needle_tip_count = tip.count;
  e.tumour_now_rms_m = now.rms_m();
  e.tumour_ahead_rms_m = ahead.rms_m();
  e.needle_tip_rms_m = tip.rms_m();
  if (e.horizon_ns > 0) {
    char name[64];
    std::snprintf(name, sizeof(name), "tumour at +%.0f ms", 1e-6 * static_cast<double>(e.horizon_ns));
    ahead.series.name = name;
  }
  for (ErrorCurve* curve : {&now, &ahead, &tip})
    if (curve->count > 0) e.series.push_back(std::move(curve->series));
  return e;
}

std::string format_evaluation(const Evaluation& e, TimeNs settle_ns) {
  char text[768];
  std::snprintf(text, sizeof(text),
                "prediction error against the simulated patient's truth (RMS from %.1f s after its first sample):\n"
                "  tumour now        %8.2f mm  (%lld predictions)\n"
                "  tumour at +%3.0f ms %7.2f mm  (%lld predictions)\n"
                "  needle tip        %8.2f mm  (%lld needle states)\n"
                "  outputs without a truth to compare: %lld\n"
                "station tick to this reader: median %.0f us, p99 %.0f us, max %.0f us (%lld predictions)\n",
                1e-9 * static_cast<double>(settle_ns), 1e3 * e.tumour_now_rms_m,
                static_cast<long long>(e.tumour_now_count), 1e-6 * static_cast<double>(e.horizon_ns),
                1e3 * e.tumour_ahead_rms_m, static_cast<long long>(e.tumour_ahead_count), 1e3 * e.needle_tip_rms_m,
                static_cast<long long>(e.needle_tip_count), static_cast<long long>(e.without_truth),
                e.tick_to_reader.median_us, e.tick_to_reader.p99_us, e.tick_to_reader.max_us,
                static_cast<long long>(e.tick_to_reader.count));
  std::string out = text;
  out += "predictions of the tumour by liver rung:";
  for (const auto& [rung, count] : e.predictions_by_rung)
    out += " " + std::to_string(rung) + ": " + std::to_string(count) + ";";
  return out + "\n";
}

std::string evaluation_json(const Evaluation& e) {
  char text[768];
  std::snprintf(
      text, sizeof(text),
      "{\n  \"tumour_now_rms_mm\": %.4f, \"tumour_now_count\": %lld,\n  \"tumour_ahead_rms_mm\": %.4f, "
      "\"tumour_ahead_count\": %lld,"
      " \"horizon_ms\": %.1f,\n  \"needle_tip_rms_mm\": %.4f, \"needle_tip_count\": %lld,\n  \"without_truth\": %lld,\n"
      "  \"tick_to_reader_us\": {\"median\": %.1f, \"p99\": %.1f, \"max\": %.1f, \"count\": %lld},\n",
      1e3 * e.tumour_now_rms_m, static_cast<long long>(e.tumour_now_count), 1e3 * e.tumour_ahead_rms_m,
      static_cast<long long>(e.tumour_ahead_count), 1e-6 * static_cast<double>(e.horizon_ns), 1e3 * e.needle_tip_rms_m,
      static_cast<long long>(e.needle_tip_count), static_cast<long long>(e.without_truth), e.tick_to_reader.median_us,
      e.tick_to_reader.p99_us, e.tick_to_reader.max_us, static_cast<long long>(e.tick_to_reader.count));
  std::string out = text;
  out += "  \"predictions_by_rung\": {";
  for (const auto& [rung, count] : e.predictions_by_rung)
    out += (rung == e.predictions_by_rung.begin()->first ? "\"" : ", \"") + std::to_string(rung) +
           "\": " + std::to_string(count);
  return out + "}\n}\n";
}

}  // namespace nav::station
