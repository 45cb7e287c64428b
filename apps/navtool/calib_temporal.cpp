// navtool calib temporal: the video-to-tracker lag of a water-tank recording (the tank
// bottom's line depth in the frames against the probe's tracked position along its motion),
// by cross-correlation with an uncertainty; prints it and optionally writes it as
// "key = value" lines (a time offset has no place among the URDF's joint origins).
#include <cstdio>
#include <cstdlib>
#include <fstream>

#include "calib_common.hpp"
#include "commands.hpp"
#include "nav/calibration/temporal_calibration.hpp"
#include "nav/calibration/temporal_calibration_signals.hpp"
#include "nav/ultrasound/plus_sequence.hpp"
#include "nav/ultrasound/plus_transform.hpp"

namespace navtool {

int calib_temporal(const std::vector<std::string>& args) {
  const auto options =
      CalibOptions::parse(args, {"--video", "--tracker", "--probe", "--reference", "--max-lag-s", "--out"});
  if (!options) return exit_bad_input;
  if (!options->has("--video") || !options->has("--tracker")) {
    return report_error({"--video FILE.mha and --tracker FILE.mha are required", "", 0, "--video"});
  }
  const auto video = nav::ultrasound::read_plus_sequence(options->get("--video"));
  if (!video) return report_error(video.error());
  const auto tracker = nav::ultrasound::read_plus_sequence(options->get("--tracker"), {.max_frames = 0});
  if (!tracker) return report_error(tracker.error());

  nav::calibration::TimedSignal line;
  const auto& frames = video.value();
  for (std::size_t i = 0; i < frames.frames_read; ++i) {
    const int width = static_cast<int>(frames.width_px), height = static_cast<int>(frames.height_px);
    const auto row = nav::calibration::bright_line_row_px(frames.frame(i), width, height, {0, 0, width, height});
    if (!row || !frames.image_valid[i]) continue;
    line.times_s.push_back(frames.timestamps_s[i]);
    line.values.push_back(*row);
  }
  const std::string probe_name = options->get("--probe", "ProbeToTracker");
  const std::string reference_name = options->get("--reference", "ReferenceToTracker");
  const auto* probe = tracker.value().find_transform(probe_name);
  const auto* reference = tracker.value().find_transform(reference_name);
  if (probe == nullptr)
    return report_error({"no such transform in the recording", options->get("--tracker"), 0, probe_name});
  if (reference == nullptr)
    return report_error({"no such transform in the recording", options->get("--tracker"), 0, reference_name});
  std::vector<double> times;
  std::vector<Eigen::Vector3d> positions;
  for (std::size_t i = 0; i < tracker.value().frame_count; ++i) {
    if (!probe->valid[i] || !reference->valid[i]) continue;
    times.push_back(tracker.value().timestamps_s[i]);
    positions.push_back((nav::ultrasound::rigid_transform_m(reference->matrices_mm[i]).inverse() *
                         nav::ultrasound::rigid_transform_m(probe->matrices_mm[i]))
                            .translation());
  }
  nav::calibration::TemporalOptions temporal;
  char* end = nullptr;
  const std::string max_lag = options->get("--max-lag-s", "0.5");
  temporal.max_lag_s = std::strtod(max_lag.c_str(), &end);
  if (end == max_lag.c_str() || *end != '\0' || !(temporal.max_lag_s > 0.0)) {
    return report_error({"expected a positive number of seconds", "", 0, "--max-lag-s"});
  }
  if (line.times_s.size() < 2)
    return report_error({"fewer than two frames show the line", options->get("--video"), 0, ""});
  // The motion's direction over the video's span, as PLUS takes it (less the search window at each end).
  const auto motion = nav::calibration::principal_motion(times, positions, line.times_s.front() + temporal.max_lag_s,
                                                         line.times_s.back() - temporal.max_lag_s);
  const auto estimate = nav::calibration::estimate_lag(motion, line, temporal);
  if (!estimate) {
    nav::Error error = estimate.error();
    error.file = options->get("--video");
    return report_error(error);
  }
  const auto& lag = estimate.value();
  std::printf(
      "video lags the tracker by %.2f ms +- %.2f ms (correlation %.3f, %zu of %zu frames with the line, %zu "
      "tracker samples in their span)\n",
      1e3 * lag.lag_s, 1e3 * lag.uncertainty_s, lag.correlation, line.times_s.size(), frames.frames_read,
      motion.times_s.size());
  if (!options->has("--out")) return exit_ok;
  std::ofstream out(options->get("--out"));
  out << "# navtool calib temporal: subtract video_lag_s from the video's time stamps\n"
      << "video_lag_s = " << lag.lag_s << "\nuncertainty_s = " << lag.uncertainty_s
      << "\ncorrelation = " << lag.correlation << '\n';
  if (!out) return report_error({"cannot write", options->get("--out"), 0, ""});
  std::printf("wrote %s\n", options->get("--out").c_str());
  return exit_ok;
}

}  // namespace navtool
