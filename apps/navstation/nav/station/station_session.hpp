#pragma once
// One run of a station scene on its simulated world, from the scene to the figures: builds
// the station's liver and loop and the world, runs the station in real time (two threads;
// the devices and the station on DDS by default, with the deformed surface published),
// replays the same recording without its ultrasound observations for the open-loop figures,
// and scores both against the full-order truth. Also formats the summary, a JSON report and
// the error plot. Init/report-time code.
#include <functional>
#include <string>
#include <vector>

#include "nav/core/error.hpp"
#include "nav/station/display_surface.hpp"
#include "nav/station/error_plot.hpp"
#include "nav/station/scene.hpp"
#include "nav/station/simulated_world.hpp"
#include "nav/station/station_liver.hpp"
#include "nav/station/station_run.hpp"

namespace nav::station {

/// What a session runs.
struct SessionOptions {
  WorldOptions world;                   ///< world.duration_ns is the run's length
  TimeNs settle_ns = 1 * kNsPerSecond;  ///< errors are scored from here (the filter's start-up)
  TimeNs miss_threshold_ns = 5 * kNsPerMs;
  bool lock_memory = true;  ///< false: the scene's lock_memory is not applied
  bool dds = true;          ///< devices and station on DDS (the scene's domain); false: direct hand-off
};

/// Called once the session is built, just before the station runs (e.g. to start a display
/// of the liver's surface); an error stops the session.
using BeforeRun = std::function<Status(const DisplaySurface&)>;

/// A finished session.
struct StationSession {
  StationLiver liver;
  DisplaySurface surface;  ///< the liver's boundary, published deformed on DDS
  SimulatedWorld world;
  StationRun run;                         ///< real time, with assimilation
  StationReplay open_loop;                ///< replay without ultrasound observations
  PredictionErrors assimilated, without;  ///< from settle_ns
  TimeNs display_latency_ns = 0;
  TimeNs settle_ns = 0;
  TimeNs miss_threshold_ns = 0;
  std::string liver_model;              ///< describe_station_loop: which liver the loop ran
  double build_s = 0.0, world_s = 0.0;  ///< start-up: liver and reduced loop; full-order world
};

/// Runs `scene` for options.world.duration_ns.
Result<StationSession> run_session(const Scene& scene, const SessionOptions& options, const BeforeRun& before_run = {});

/// A live run: the station alone, its devices other processes on DDS (navdevice).
struct LiveSession {
  StationLiver liver;
  DisplaySurface surface;
  StationRun run;
  TimeNs miss_threshold_ns = 0;
  std::string liver_model;                         ///< describe_station_loop: which liver the loop ran
  double build_s = 0.0;                            ///< start-up: liver and reduced loop
  std::int64_t resident_after_start_up_bytes = 0;  ///< the process's resident memory once built
  std::int64_t resident_at_end_bytes = 0;          ///< at the end of the run (its growth: a leak)
  std::int64_t peak_resident_bytes = 0;            ///< its largest, at the end of the run
};

/// Runs the station of `scene` for `duration_ns` (or until `stop`, when given, is raised) on
/// whatever devices publish on its topics. It cannot score itself: `navtool evaluate`
/// compares its predictions with a simulated patient's truth.
Result<LiveSession> run_live_session(const Scene& scene, TimeNs duration_ns, const BeforeRun& before_run = {},
                                     const std::atomic<bool>* stop = nullptr);

/// The printed summary: setup, prediction errors with and without assimilation, timing.
std::string format_summary(const Scene& scene, const StationSession& session);

/// A live run's figures as JSON: the liver model, start-up time, resident memory, tick
/// statistics and the samples taken (navstation --live --json).
std::string live_session_json(const Scene& scene, const LiveSession& session);

/// A stretch of ticks whose outputs were degraded, with every health flag raised in it.
struct DegradedPeriod {
  TimeNs from_ns = 0, to_ns = 0;  ///< the first and last degraded tick (run time)
  std::uint32_t flags = 0;        ///< HealthFlag bits
};

/// What a degraded period is of: the loop's outputs (any flag that degrades them, e.g. the
/// reduced liver out of its training envelope) or the tracked needle's input alone.
enum class DegradedWhat { outputs, needle_input };

/// The degraded stretches of a run's ticks, in time order.
std::vector<DegradedPeriod> degraded_periods(const std::vector<TickRecord>& ticks, DegradedWhat what);

/// The printed summary of a live run: setup, when and why it was degraded, timing, what
/// arrived and what was refused.
std::string format_live_summary(const Scene& scene, const LiveSession& session);

/// The same figures as one JSON object.
std::string session_json(const Scene& scene, const StationSession& session);

/// The run options of `scene`'s real-time setup (lock_memory false: not applied whatever the scene says).
StationRunOptions station_run_options(const Scene& scene, TimeNs duration_ns, TimeNs miss_threshold_ns,
                                      bool lock_memory);

/// The DDS options of `scene` (domain, topic names, arrival window, pose bounds), publishing `surface` when given.
Result<DdsRunOptions> dds_run_options(const Scene& scene, const DisplaySurface* surface);

/// The tumour's errors over time (now and ahead, with and without assimilation), in millimetres.
std::vector<PlotSeries> error_series(const StationSession& session);

}  // namespace nav::station
