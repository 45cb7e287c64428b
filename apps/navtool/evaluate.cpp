// navtool evaluate: a station's predictions and modelled needle against a simulated patient's
// truth (navdevice sim), received live on the scene's topics for --seconds or read from a
// recording of them (navtool record), with the error plot (evaluation.hpp).
#include <cstdio>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "commands.hpp"
#include "nav/core/text_file.hpp"
#include "nav/dds/recording_file.hpp"
#include "nav/dds/sample_codec.hpp"
#include "nav/dds/sample_sink.hpp"
#include "nav/dds/stop_request.hpp"
#include "nav/station/evaluation.hpp"
#include "nav/station/scene.hpp"
#include "nav/station/station_dds.hpp"

namespace navtool {
namespace {

using nav::TimeNs;

struct EvaluateArgs {
  std::string scene_path, recording_path, plot_path, json_path;
  double seconds = 10.0, settle_s = 1.0;
  long domain_id = -1;  ///< -1: the scene's
};

std::optional<EvaluateArgs> parse(const std::vector<std::string>& args) {
  EvaluateArgs parsed;
  for (std::size_t i = 1; i < args.size(); ++i) {
    const bool has_value = i + 1 < args.size();
    try {
      if (args[i] == "--scene" && has_value)
        parsed.scene_path = args[++i];
      else if (args[i] == "--recording" && has_value)
        parsed.recording_path = args[++i];
      else if (args[i] == "--seconds" && has_value)
        parsed.seconds = std::stod(args[++i]);
      else if (args[i] == "--settle-s" && has_value)
        parsed.settle_s = std::stod(args[++i]);
      else if (args[i] == "--domain" && has_value)
        parsed.domain_id = std::stol(args[++i]);
      else if (args[i] == "--plot" && has_value)
        parsed.plot_path = args[++i];
      else if (args[i] == "--json" && has_value)
        parsed.json_path = args[++i];
      else
        return std::nullopt;
    } catch (const std::exception&) {
      return std::nullopt;
    }
  }
  const bool valid = parsed.scene_path.empty() != parsed.recording_path.empty() && parsed.seconds > 0.0 &&
                     parsed.settle_s >= 0.0 && parsed.domain_id >= -1 && parsed.domain_id <= 232;
  return valid ? std::optional<EvaluateArgs>(parsed) : std::nullopt;
}

nav::station::TimedTip tip_of(const nav::dds::NeedleState& needle) {
  return {needle.source_time_ns,
          needle.point_count > 0 ? needle.shape_points_m[needle.point_count - 1] : nav::dds::Vector3{}};
}

/// Receives the scene's predictions, needle states and truth for `seconds` (or until SIGINT/SIGTERM).
nav::Result<nav::station::EvaluationInput> receive(const nav::station::Scene& scene, double seconds) {
  // The sinks outlive the participant whose listeners fill them (made first, destroyed last).
  auto predictions = std::make_unique<nav::dds::RingSink<nav::dds::TargetPrediction, 256>>();
  auto needles = std::make_unique<nav::dds::RingSink<nav::dds::NeedleState, 64>>();
  auto truths = std::make_unique<nav::dds::RingSink<nav::dds::GroundTruth, 256>>();
  auto node =
      nav::station::make_station_node(scene.topics.domain_id, "navtool_evaluate",
                                      nav::station::topic_names(scene.topics), scene.network, nav::station::Role::tool);
  if (!node.ok()) return node.error();
  for (const nav::Status& status :
       {node.value()->subscribe(*predictions), node.value()->subscribe(*needles), node.value()->subscribe(*truths)})
    if (!status.ok()) return status.error();
  nav::dds::install_stop_handlers();
  nav::station::EvaluationInput input;
  auto needle = std::make_unique<nav::dds::NeedleState>();
  nav::dds::TargetPrediction prediction;
  nav::dds::GroundTruth truth;
  nav::MonotonicClock clock;
  const TimeNs until_ns = clock.now_ns() + static_cast<TimeNs>(seconds * 1e9);
  for (bool last = false; !last;) {
    last = nav::dds::stop_requested() || clock.now_ns() >= until_ns;
    while (predictions->try_pop(prediction)) input.predictions.push_back(prediction);
    while (needles->try_pop(*needle)) input.needle_tips.push_back(tip_of(*needle));
    while (truths->try_pop(truth)) input.truths.push_back(truth);
    clock.sleep_until_ns(clock.now_ns() + 2 * nav::kNsPerMs);
  }
  const nav::dds::BoundaryCounts counts = node.value()->boundary_counts();
  std::printf("received %zu predictions, %zu needle states, %zu truths (dropped at the boundary: %s)\n",
              input.predictions.size(), input.needle_tips.size(), input.truths.size(),
              nav::dds::drops_by_reason(counts).c_str());
  return input;
}

/// Decodes the record into `out` when it is of the sample's topic; false for a damaged payload.
template <typename Sample, typename Sink>
bool take_if_of(const nav::dds::RecordedSample& record, Sample& sample, Sink sink) {
  if (record.topic != nav::dds::topic_of<Sample>()) return true;
  if (nav::dds::decode_sample(record.payload.data(), record.payload.size(), sample) != nav::dds::SampleFault::none)
    return false;
  sink(sample);
  return true;
}

/// Reads the predictions, needle states and truth of a recording (its intact part when damaged).
nav::Result<nav::station::EvaluationInput> read_recording(const std::string& path) {
  auto reader = nav::dds::RecordingReader::open(path);
  if (!reader.ok()) return reader.error();
  if (reader.value()->damage())
    std::fprintf(stderr, "navtool evaluate: %s; reading its intact part\n",
                 reader.value()->damage()->describe().c_str());
  nav::station::EvaluationInput input;
  auto needle = std::make_unique<nav::dds::NeedleState>();
  nav::dds::TargetPrediction prediction;
  nav::dds::GroundTruth truth;
  std::size_t damaged = 0;
  for (std::size_t i = 0; i < reader.value()->record_count(); ++i) {
    auto record = reader.value()->read(i);
    if (!record.ok()) {
      ++damaged;
      continue;
    }
    const TimeNs received_ns = record.value().receive_time_ns;
    const bool decoded =
        take_if_of(record.value(), prediction,
                   [&](auto p) {
                     p.receive_time_ns = received_ns;  // when the recorder took it
                     input.predictions.push_back(p);
                   }) &&
        take_if_of(record.value(), *needle, [&](const auto& n) { input.needle_tips.push_back(tip_of(n)); }) &&
        take_if_of(record.value(), truth, [&](const auto& t) { input.truths.push_back(t); });
    damaged += decoded ? 0 : 1;
  }
  std::printf("read %zu predictions, %zu needle states, %zu truths from %s (%zu records damaged)\n",
              input.predictions.size(), input.needle_tips.size(), input.truths.size(), path.c_str(), damaged);
  return input;
}

bool write_text(const std::string& path, const std::string& text) {
  const nav::Status written = nav::write_text_file(path, text);
  if (!written.ok()) std::fprintf(stderr, "navtool evaluate: %s\n", written.error().describe().c_str());
  return written.ok();
}

}  // namespace

int evaluate(const std::vector<std::string>& args) {
  const std::optional<EvaluateArgs> parsed = parse(args);
  if (!parsed) {
    std::fputs(
        "usage: navtool evaluate (--scene FILE [--seconds S] [--domain D] | --recording FILE.navrec) [--settle-s S]"
        " [--plot FILE.svg] [--json FILE]\n",
        stderr);
    return exit_bad_input;
  }
  nav::Result<nav::station::EvaluationInput> input = nav::Error{.message = ""};
  if (!parsed->recording_path.empty()) {
    input = read_recording(parsed->recording_path);
  } else {
    auto scene = nav::station::load_scene(parsed->scene_path);
    if (!scene.ok()) {
      std::fprintf(stderr, "navtool evaluate: %s\n", scene.error().describe().c_str());
      return exit_bad_input;
    }
    if (parsed->domain_id >= 0) scene.value().topics.domain_id = static_cast<std::uint32_t>(parsed->domain_id);
    input = receive(scene.value(), parsed->seconds);
  }
  if (!input.ok()) {
    std::fprintf(stderr, "navtool evaluate: %s\n", input.error().describe().c_str());
    return exit_bad_input;
  }
  const auto settle_ns = static_cast<TimeNs>(parsed->settle_s * 1e9);
  const nav::station::Evaluation evaluation = nav::station::evaluate(std::move(input).value(), settle_ns);
  std::printf("%s", nav::station::format_evaluation(evaluation, settle_ns).c_str());
  bool written = true;
  if (!parsed->plot_path.empty())
    written = write_text(parsed->plot_path,
                         nav::station::error_plot_svg("station prediction error against the truth", evaluation.series));
  if (!parsed->json_path.empty())
    written = write_text(parsed->json_path, nav::station::evaluation_json(evaluation)) && written;
  if (evaluation.tumour_now_count == 0) {
    std::fprintf(stderr,
                 "navtool evaluate: no prediction had a truth to compare: are a station and navdevice sim running on "
                 "this domain?\n");
    return exit_failure;
  }
  return written ? exit_ok : exit_failure;
}

}  // namespace navtool
