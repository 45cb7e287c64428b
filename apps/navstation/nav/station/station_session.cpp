#include "nav/station/station_session.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <utility>

#include "nav/core/health_names.hpp"
#include "nav/dds/sample_fault.hpp"
#include "nav/station/format_numbers.hpp"
#include "nav/station/station_build.hpp"
#include "nav/station/station_dds.hpp"
#include "nav/station/station_loop.hpp"

namespace nav::station {

namespace {

double mebibytes(std::int64_t bytes) { return static_cast<double>(bytes) / (1024.0 * 1024.0); }

/// " I/O pin: ...; I/O SCHED_FIFO: ...": how the I/O thread's setup went.
std::string io_setup_text(const StationRun& run) {
  std::string text = std::string(" I/O pin: ") + outcome_name(run.io_pin.outcome);
  if (!run.io_fifo.name.empty()) text += std::string("; I/O SCHED_FIFO: ") + outcome_name(run.io_fifo.outcome);
  return text + "\n";
}

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

double distance_mm(const Point3& a, const Point3& b) { return 1e3 * std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]); }

/// The error of the tumour now (or ahead) at every liver step of `ticks`.
PlotSeries tumour_series(const StationSession& s, std::span<const TickRecord> ticks, bool ahead, PlotSeries style) {
  for (const TickRecord& t : ticks) {
    if (t.time_ns != t.tissue_time_ns) continue;
    const Point3 truth = s.world.tumour_at(t.tissue_time_ns + (ahead ? s.display_latency_ns : 0));
    style.x.push_back(1e-9 * static_cast<double>(t.time_ns));
    style.y.push_back(distance_mm(ahead ? t.tumour_ahead_m : t.tumour_now_m, truth));
  }
  return style;
}

}  // namespace

StationRunOptions station_run_options(const Scene& scene, TimeNs duration_ns, TimeNs miss_threshold_ns,
                                      bool lock_memory) {
  StationRunOptions run_options;
  run_options.duration_ns = duration_ns;
  run_options.miss_threshold_ns = miss_threshold_ns;
  run_options.realtime = {scene.station.realtime_core, scene.station.realtime_priority,
                          scene.station.lock_memory && lock_memory};
  run_options.io_core = scene.station.io_core;
  run_options.io_priority = scene.station.io_priority;
  return run_options;
}

Result<DdsRunOptions> dds_run_options(const Scene& scene, const DisplaySurface* surface) {
  auto reference_from_model = scene_reference_from_model(scene);
  if (!reference_from_model.ok()) return reference_from_model.error();
  DdsRunOptions dds;
  dds.reference_from_model = reference_from_model.value();
  dds.simulated_tracker_from_reference = scene.devices.tracker.tracker_from_reference;
  dds.domain_id = scene.topics.domain_id;
  dds.topic_names = topic_names(scene.topics);
  dds.network = scene.network;
  dds.tools = scene.devices.tracker.tools;
  dds.surface = surface;
  const DeviceClockSettings& clock = scene.devices.clock;
  dds.arrival = {.source_clock_offset_ns = static_cast<TimeNs>(clock.offset_ms * 1e6),
                 .max_ahead_ns = static_cast<TimeNs>(clock.max_ahead_ms * 1e6),
                 .max_behind_ns = static_cast<TimeNs>(clock.max_behind_ms * 1e6)};
  dds.bad_sample_hold_ns = static_cast<TimeNs>(clock.bad_sample_hold_ms * 1e6);
  dds.pose_bounds.volume_radius_m = scene.devices.tracker.volume_radius_m;
  dds.pose_bounds.max_speed_m_per_s = scene.devices.tracker.max_speed_m_per_s;
  return dds;
}

namespace {

/// The station's own side of a session: its liver, reduced loop and display surface.
struct StationParts {
  StationLiver liver;
  OperatingLoopModel loop;
  DisplaySurface surface;
  double build_s = 0.0;  ///< liver and reduced loop
};

/// Builds the station's parts of `scene`, then calls before_run (if any) with its surface.
Result<StationParts> build_station_parts(const Scene& scene, const BreathingGeometry& breathing,
                                         const BeforeRun& before_run) {
  if (const Status runnable = check_station_loop(scene); !runnable.ok())
    return runnable.error();  // before anything is built
  const auto start = std::chrono::steady_clock::now();
  auto liver = make_station_liver(scene);
  if (!liver.ok()) return liver.error();
  auto loop = make_station_loop(liver.value(), scene, breathing, StationLoopSettings{});
  if (!loop.ok()) return loop.error();
  const double build_s = seconds_since(start);
  auto surface = make_display_surface(liver.value().mesh);
  if (!surface.ok())
    return Error{.message = surface.error().describe(),
                 .file = scene.source_path,
                 .line = scene.liver.line,
                 .field = "liver.mesh"};
  if (before_run) {
    const Status ready = before_run(surface.value());
    if (!ready.ok()) return ready.error();
  }
  return StationParts{std::move(liver).value(), std::move(loop).value(), std::move(surface).value(), build_s};
}

}  // namespace

Result<StationSession> run_session(const Scene& scene, const SessionOptions& options, const BeforeRun& before_run) {
  if (const Status simulated = check_simulated_devices(scene); !simulated.ok())
    return simulated.error();  // before anything is built
  StationSession s;
  const BreathingGeometry breathing;
  auto parts = build_station_parts(scene, breathing, before_run);
  if (!parts.ok()) return parts.error();
  StationParts& p =
      parts.value();  // the run publishes p.surface: the liver and the surface move into the session at its end
  const OperatingLoopModel& loop = p.loop;
  s.build_s = p.build_s;
  s.liver_model = describe_station_loop(scene, loop);
  const auto start = std::chrono::steady_clock::now();
  auto world = simulate_world(p.liver, scene, breathing, options.world);
  if (!world.ok()) return world.error();
  s.world = std::move(world).value();
  s.world_s = seconds_since(start);

  StationRunOptions run_options =
      station_run_options(scene, options.world.duration_ns, options.miss_threshold_ns, options.lock_memory);
  if (options.dds) {
    auto dds = dds_run_options(scene, &p.surface);
    if (!dds.ok()) return dds.error();
    run_options.dds = std::move(dds).value();
  }
  auto run = run_station(loop, s.world, run_options);
  if (!run.ok()) return run.error();
  s.run = std::move(run).value();
  auto open_loop = replay_station(loop, s.world.samples, options.world.duration_ns, false);
  if (!open_loop.ok()) return open_loop.error();
  s.open_loop = std::move(open_loop).value();
  s.display_latency_ns = loop.options.display_latency_ns;
  s.settle_ns = options.settle_ns;
  s.miss_threshold_ns = options.miss_threshold_ns;
  s.assimilated = prediction_errors(s.world, s.run.ticks, s.display_latency_ns, options.settle_ns);
  s.without = prediction_errors(s.world, s.open_loop.ticks, s.display_latency_ns, options.settle_ns);
  s.liver = std::move(p.liver);
  s.surface = std::move(p.surface);
  return s;
}

Result<LiveSession> run_live_session(const Scene& scene, TimeNs duration_ns, const BeforeRun& before_run,
                                     const std::atomic<bool>* stop) {
  LiveSession s;
  auto parts = build_station_parts(scene, BreathingGeometry{}, before_run);
  if (!parts.ok()) return parts.error();
  StationParts& p =
      parts.value();  // the run publishes p.surface: the liver and the surface move into the session at its end
  const OperatingLoopModel& loop = p.loop;
  s.build_s = p.build_s;
  s.liver_model = describe_station_loop(scene, loop);
  s.resident_after_start_up_bytes = resident_bytes();
  s.miss_threshold_ns = 5 * kNsPerMs;
  StationRunOptions run_options = station_run_options(scene, duration_ns, s.miss_threshold_ns, true);
  auto dds = dds_run_options(scene, &p.surface);
  if (!dds.ok()) return dds.error();
  run_options.dds = std::move(dds).value();
  run_options.stop = stop;
  auto imaging = scene_probe_imaging(scene);
  if (!imaging.ok()) return imaging.error();
  auto run = run_live_station(loop, imaging.value(), run_options);
  if (!run.ok()) return run.error();
  s.run = std::move(run).value();
  s.resident_at_end_bytes = resident_bytes();
  s.peak_resident_bytes = peak_resident_bytes();
  s.liver = std::move(p.liver);
  s.surface = std::move(p.surface);
  return s;
}

namespace {

/// The modelled needle's largest tip force and its punctures over a run.
struct NeedlePeaks {
  double tip_force_n = 0.0;
  int punctures = 0;
};

NeedlePeaks needle_peaks(const std::vector<TickRecord>& ticks) {
  NeedlePeaks peaks;
  for (const TickRecord& t : ticks)
    peaks.tip_force_n = std::max(peaks.tip_force_n, t.tip_force_n),
    peaks.punctures = std::max(peaks.punctures, t.punctures);
  return peaks;
}

/// The figures of a real-time run: timing, the I/O thread, the ultrasound and DDS.
std::string run_figures(const Scene& scene, const StationRun& run, const DisplaySurface& surface,
                        TimeNs miss_threshold_ns) {
  const StepStatistics& t = run.steps;
  std::string out;
  out += format_numbers("step time over %.0f ticks: median %.1f us, p99 %.1f us, p99.9 %.1f us",
                        static_cast<double>(t.ticks), t.median_us, t.p99_us, t.p999_us);
  out += format_numbers(", p99.99 %.1f us, max %.1f us\n", t.p9999_us, t.max_us);
  out += format_numbers("tick lateness: jitter (std) %.1f us, p99 %.1f us, p99.99 %.1f us, max %.1f us (tick %.0f)\n",
                        t.jitter_us, t.lateness_p99_us, t.lateness_p9999_us, t.max_lateness_us,
                        static_cast<double>(t.latest_tick));
  out += format_numbers("deadline misses (> %.0f ms late): %.0f (> 1 ms late: %.0f), skipped ticks: %.0f\n",
                        1e-6 * static_cast<double>(miss_threshold_ns), static_cast<double>(t.deadline_misses),
                        static_cast<double>(t.late_over_1ms), static_cast<double>(t.skipped_ticks));
  out += format_numbers("I/O thread: %.0f samples pushed, %.0f outputs read\n", static_cast<double>(run.samples_pushed),
                        static_cast<double>(run.outputs_read));
  const ObserverCounts& u = run.observer;
  out += format_numbers(
      "ultrasound: %.0f B-mode frames, %.0f tumour points found (dropped: %.0f without a confident detection, %.0f "
      "without a probe pose)\n",
      static_cast<double>(u.frames), static_cast<double>(u.observations), static_cast<double>(u.dropped_no_detection),
      static_cast<double>(u.dropped_no_pose));
  out += format_numbers("  tumour tracker per frame (I/O thread): median %.2f ms, p99 %.2f ms\n",
                        1e-3 * run.frame_processing.median_us, 1e-3 * run.frame_processing.p99_us);
  if (run.dds) {
    const DdsRunReport& d = *run.dds;
    out += format_numbers(
        "DDS (domain %.0f; shared memory and UDP on 127.0.0.1): %.0f poses and %.0f frames received, %.0f outputs "
        "published\n",
        static_cast<double>(scene.topics.domain_id), static_cast<double>(d.poses_received),
        static_cast<double>(d.frames_received), static_cast<double>(d.outputs_published));
    if (d.forces_published > 0 || d.forces_dropped > 0)
      out += format_numbers("  needle forces at the loop rate: %.0f published, %.0f dropped\n",
                            static_cast<double>(d.forces_published), static_cast<double>(d.forces_dropped));
    if (d.pose_latency.count > 0)  // the devices in this process: their write times are known
      out += format_numbers(
          "  writer to reader: poses median %.0f us, p99 %.0f us; frames median %.0f us, p99 %.0f us\n",
          d.pose_latency.median_us, d.pose_latency.p99_us, d.frame_latency.median_us, d.frame_latency.p99_us);
    out += format_numbers(
        "  deformed surface (%.0f vertices): %.0f published; reconstruction on the I/O thread median %.0f us, p99 %.0f "
        "us\n",
        static_cast<double>(surface.nodes.size()), static_cast<double>(d.surfaces_published),
        d.surface_reconstruction.median_us, d.surface_reconstruction.p99_us);
    out += format_numbers("  lost on the way (sent, never delivered): %.0f poses, %.0f frames\n",
                          static_cast<double>(d.poses_lost), static_cast<double>(d.frames_lost));
    out += format_numbers("  samples accepted %.0f;", static_cast<double>(d.boundary.accepted));
    out += " dropped at the boundary: " + dds::drops_by_reason(d.boundary) + "\n";
    if (dds::refused_as_invalid(d.boundary) > 0)
      out += "  refused by input: " + dds::refusals_by_input(d.input_refused) + "\n";
    if (const std::optional<std::uint32_t> reference = scene.devices.tracker.tools.reference)
      out += format_numbers(
          "  registered to the model through the reference (tool %.0f); poses before its first, not used: %.0f\n",
          static_cast<double>(*reference), static_cast<double>(d.unregistered_poses));
  }
  return out;
}

}  // namespace

std::string format_summary(const Scene& scene, const StationSession& s) {
  const StationSettings& st = scene.station;
  std::string out = "station '" + st.name + "': ";
  out += format_numbers("%.0f Hz loop, liver every %.0f ms, display latency %.0f ms\n", st.loop_rate_hz,
                        1e3 / st.tissue_rate_hz, 1e-6 * static_cast<double>(s.display_latency_ns));
  out += s.liver_model + "\n";
  out += format_numbers(
      "start-up: liver and reduced loop %.1f s, full-order world %.1f s (%.0f tetrahedra, %.0f samples)\n", s.build_s,
      s.world_s, static_cast<double>(s.liver.mesh.tets.size()), static_cast<double>(s.world.samples.size()));
  out += "real-time setup:";
  for (const SetupStep& step : s.run.realtime_setup) out += " " + step.name + ": " + outcome_name(step.outcome) + ";";
  out += io_setup_text(s.run);
  out += format_numbers("prediction error against the full-order truth (RMS from %.1f s, %.0f liver steps):\n",
                        1e-9 * static_cast<double>(s.settle_ns), s.assimilated.steps);
  out += "                         with assimilation   without\n";
  out += format_numbers("  tumour now              %8.2f mm        %6.2f mm\n", 1e3 * s.assimilated.tumour_now_rms_m,
                        1e3 * s.without.tumour_now_rms_m);
  out += format_numbers("  tumour at +%2.0f ms        %8.2f mm        %6.2f mm\n",
                        1e-6 * static_cast<double>(s.display_latency_ns), 1e3 * s.assimilated.tumour_ahead_rms_m,
                        1e3 * s.without.tumour_ahead_rms_m);
  out += format_numbers("  needle tip              %8.2f mm\n", 1e3 * s.assimilated.needle_tip_rms_m);
  if (!s.world.needle_tip_truth_m.empty()) {
    const NeedlePeaks n = needle_peaks(s.run.ticks);
    out += format_numbers(
        "needle (coupled to the liver): tip force peak %.2f N, %.0f punctures; the full-order truth: %.2f N, %.0f "
        "punctures\n",
        n.tip_force_n, static_cast<double>(n.punctures), s.world.needle_peak_tip_force_n,
        static_cast<double>(s.world.needle_punctures));
  }
  out += run_figures(scene, s.run, s.surface, s.miss_threshold_ns);
  return out;
}

std::vector<DegradedPeriod> degraded_periods(const std::vector<TickRecord>& ticks, DegradedWhat what) {
  std::vector<DegradedPeriod> periods;
  bool open = false;
  for (const TickRecord& t : ticks) {
    const bool degraded = what == DegradedWhat::outputs ? t.degraded : t.needle_degraded;
    if (degraded && !open) periods.push_back({t.time_ns, t.time_ns, 0});
    if (degraded)
      periods.back().to_ns = t.time_ns,
      periods.back().flags |= what == DegradedWhat::outputs ? t.health_flags : t.needle_flags;
    open = degraded;
  }
  return periods;
}

namespace {

/// One line of degraded periods, e.g. " 0.000-0.412 s (missing_input), 3.120-5.840 s (stale_input)".
std::string format_periods(const std::vector<DegradedPeriod>& periods) {
  constexpr std::size_t kPeriodsShown = 8;
  std::string out;
  for (std::size_t i = 0; i < std::min(periods.size(), kPeriodsShown); ++i) {
    const DegradedPeriod& p = periods[i];
    out += format_numbers(" %.3f-%.3f s (", 1e-9 * static_cast<double>(p.from_ns), 1e-9 * static_cast<double>(p.to_ns));
    out += health_flag_names(p.flags) + ")" + (i + 1 < periods.size() ? "," : "");
  }
  if (periods.size() > kPeriodsShown)
    out += format_numbers(" and %.0f more", static_cast<double>(periods.size() - kPeriodsShown));
  return out + (periods.empty() ? " never\n" : "\n");
}

}  // namespace

std::string format_live_summary(const Scene& scene, const LiveSession& s) {
  const StationSettings& st = scene.station;
  std::string out = "station '" + st.name + "' (live: devices on DDS): ";
  out += format_numbers("%.0f Hz loop, liver every %.0f ms, display latency %.0f ms\n", st.loop_rate_hz,
                        1e3 / st.tissue_rate_hz, st.display_latency_ms);
  out += s.liver_model + "\n";
  out += format_numbers(
      "start-up: liver and reduced loop %.1f s (%.0f tetrahedra); resident memory %.1f MiB after it, %.1f MiB at "
      "most\n",
      s.build_s, static_cast<double>(s.liver.mesh.tets.size()), mebibytes(s.resident_after_start_up_bytes),
      mebibytes(s.peak_resident_bytes));
  out += format_numbers("resident memory of the run: %.1f MiB when the loop started, %.1f MiB at its end\n",
                        mebibytes(s.run.resident_at_start_bytes), mebibytes(s.resident_at_end_bytes));
  out += "real-time setup:";
  for (const SetupStep& step : s.run.realtime_setup) out += " " + step.name + ": " + outcome_name(step.outcome) + ";";
  out += io_setup_text(s.run);
  out += "outputs degraded:" + format_periods(degraded_periods(s.run.ticks, DegradedWhat::outputs));
  out += "needle input degraded:" + format_periods(degraded_periods(s.run.ticks, DegradedWhat::needle_input));
  return out + run_figures(scene, s.run, s.surface, s.miss_threshold_ns);
}

namespace {

/// `text` as a JSON string's contents: quotes and backslashes escaped, control characters left out.
std::string json_text(const std::string& text) {
  std::string out;
  for (const char c : text) {
    if (c == '"' || c == '\\') out += '\\';
    if (static_cast<unsigned char>(c) >= 0x20) out += c;
  }
  return out;
}

/// The JSON members of a run's tick figures (each line indented, ending with a comma).
std::string steps_json(const StepStatistics& t) {
  std::string out = format_numbers(
      "  \"ticks\": %.0f, \"step_us\": {\"median\": %.3f, \"p99\": %.3f, \"p999\": %.3f, \"p9999\": %.3f,",
      static_cast<double>(t.ticks), t.median_us, t.p99_us, t.p999_us, t.p9999_us);
  out += format_numbers(
      " \"max\": %.3f},\n  \"jitter_us\": %.3f, \"lateness_us\": {\"p99\": %.3f, \"p9999\": %.3f, \"max\": %.3f},\n",
      t.max_us, t.jitter_us, t.lateness_p99_us, t.lateness_p9999_us, t.max_lateness_us);
  out += format_numbers("  \"max_lateness_us\": %.3f, \"late_over_1ms\": %.0f,", t.max_lateness_us,
                        static_cast<double>(t.late_over_1ms));
  return out + format_numbers(" \"deadline_misses\": %.0f, \"skipped_ticks\": %.0f,\n",
                              static_cast<double>(t.deadline_misses), static_cast<double>(t.skipped_ticks));
}

}  // namespace

std::string session_json(const Scene& scene, const StationSession& s) {
  std::string out = "{\n  \"scene\": \"" + json_text(scene.station.name) + "\",\n" + steps_json(s.run.steps);
  out += format_numbers("  \"tumour_now_rms_mm\": {\"assimilated\": %.4f, \"without\": %.4f},\n",
                        1e3 * s.assimilated.tumour_now_rms_m, 1e3 * s.without.tumour_now_rms_m);
  out += format_numbers("  \"tumour_ahead_rms_mm\": {\"assimilated\": %.4f, \"without\": %.4f},\n",
                        1e3 * s.assimilated.tumour_ahead_rms_m, 1e3 * s.without.tumour_ahead_rms_m);
  if (!s.world.needle_tip_truth_m.empty()) {
    const NeedlePeaks n = needle_peaks(s.run.ticks);
    out += format_numbers(
        "  \"needle\": {\"tip_force_peak_n\": %.4f, \"punctures\": %.0f, \"truth_tip_force_peak_n\": %.4f, "
        "\"truth_punctures\": %.0f},\n",
        n.tip_force_n, static_cast<double>(n.punctures), s.world.needle_peak_tip_force_n,
        static_cast<double>(s.world.needle_punctures));
  }
  out += format_numbers("  \"needle_tip_rms_mm\": %.4f, \"display_latency_ms\": %.1f\n}\n",
                        1e3 * s.assimilated.needle_tip_rms_m, 1e-6 * static_cast<double>(s.display_latency_ns));
  return out;
}

std::string live_session_json(const Scene& scene, const LiveSession& s) {
  std::string out = "{\n  \"scene\": \"" + json_text(scene.station.name) + "\",\n  \"liver_model\": \"" +
                    json_text(s.liver_model) + "\",\n";
  out += format_numbers("  \"start_up_s\": %.3f, \"resident_mib\": {\"after_start_up\": %.2f, \"peak\": %.2f,",
                        s.build_s, mebibytes(s.resident_after_start_up_bytes), mebibytes(s.peak_resident_bytes));
  out += format_numbers(" \"at_loop_start\": %.2f, \"at_end\": %.2f},\n", mebibytes(s.run.resident_at_start_bytes),
                        mebibytes(s.resident_at_end_bytes));
  out += steps_json(s.run.steps);
  const DdsRunReport d = s.run.dds.value_or(DdsRunReport{});
  out += format_numbers(
      "  \"poses_received\": %.0f, \"frames_received\": %.0f, \"samples_accepted\": %.0f, \"samples_refused\": %.0f,",
      static_cast<double>(d.poses_received), static_cast<double>(d.frames_received),
      static_cast<double>(d.boundary.accepted), static_cast<double>(dds::refused_as_invalid(d.boundary)));
  out += format_numbers(" \"poses_lost\": %.0f, \"frames_lost\": %.0f,", static_cast<double>(d.poses_lost),
                        static_cast<double>(d.frames_lost));
  out += "\n  \"refused_by_input\": {";
  for (std::size_t i = 0; i < dds::kStationInputCount; ++i)
    out += std::string(i == 0 ? "\"" : ", \"") + dds::station_input_name(static_cast<dds::StationInput>(i)) +
           "\": " + std::to_string(d.input_refused[i]);
  out += "},";
  out += format_numbers(" \"forces_published\": %.0f, \"forces_dropped\": %.0f,",
                        static_cast<double>(d.forces_published), static_cast<double>(d.forces_dropped));
  return out + format_numbers(" \"outputs_published\": %.0f\n}\n", static_cast<double>(d.outputs_published));
}

std::vector<PlotSeries> error_series(const StationSession& s) {
  const std::string ahead = format_numbers("tumour at +%.0f ms", 1e-6 * static_cast<double>(s.display_latency_ns));
  return {tumour_series(s, s.run.ticks, false, {"tumour now, assimilated", "#1f77b4", false, {}, {}}),
          tumour_series(s, s.run.ticks, true, {ahead + ", assimilated", "#2ca02c", false, {}, {}}),
          tumour_series(s, s.open_loop.ticks, false, {"tumour now, without", "#d62728", true, {}, {}}),
          tumour_series(s, s.open_loop.ticks, true, {ahead + ", without", "#ff7f0e", true, {}, {}})};
}

}  // namespace nav::station
