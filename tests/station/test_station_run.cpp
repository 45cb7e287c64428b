// The running station on the demo scene's simulated world (the embedded liver simulated by the
// full-order corotational model under a breathing diaphragm that the respiratory marker only
// approximates; a tracker at 60 Hz with 10 ms latency and 0.25 mm noise; B-mode frames at
// 20 Hz in which the station finds the tumour itself). Checked: the recording keeps to the
// scene's rates, latencies and noise, and breathing moves the true tumour; the tumour points
// found in the frames are within a millimetre of the truth; the two-thread real-time run
// (direct hand-off) at 1 kHz for 10 s keeps every deadline its host leaves it (a stall witness
// on each core tells the host's stalls: core_stall_witness.hpp; on a quiet host that is no
// tick more than 100 ms late and 9500 ticks or more; the real figures are printed); the same recording
// replayed twice on a SimulatedClock gives bitwise-identical outputs, and a changed sample
// changes them; the tumour predicted with assimilation is within 1 mm RMS of the truth and
// better than without; the scene's needle pushes and punctures the liver's capsule in the world
// (full-order coupling) and in the loop (reduced coupling), and on a patient as the scene says
// its modelled tip follows the true one within a millimetre; `navstation --scene FILE --seconds 2 --images DIR` on the
// demo scene with renamed topics runs on DDS, prints its summary and has navview write images.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include "core_stall_witness.hpp"
#include "demo_station.hpp"
#include "support/run_command.hpp"

namespace nav::station {
namespace {

constexpr TimeNs kDuration = 10 * kNsPerSecond;
constexpr TimeNs kSettled = 1 * kNsPerSecond;  // errors scored from here (the filter's start-up)

using testing::DemoStation;

const DemoStation& demo() {
  static const DemoStation built(kDuration);
  return built;
}

/// The recording as the loop sees it (frames replaced by tumour points; built once).
const std::vector<DeviceSample>& observed() {
  static const std::vector<DeviceSample> samples = observed_recording(demo().world, TumourObserverOptions{});
  return samples;
}

bool same_records(const std::vector<TickRecord>& a, const std::vector<TickRecord>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (a[i].time_ns != b[i].time_ns || a[i].tissue_time_ns != b[i].tissue_time_ns ||
        std::memcmp(a[i].tumour_now_m.data(), b[i].tumour_now_m.data(), sizeof(Point3)) != 0 ||
        std::memcmp(a[i].tumour_ahead_m.data(), b[i].tumour_ahead_m.data(), sizeof(Point3)) != 0 ||
        std::memcmp(a[i].needle_tip_m.data(), b[i].needle_tip_m.data(), sizeof(Point3)) != 0)
      return false;
  return true;
}

TEST(StationRun, TheSimulatedDevicesKeepToTheScene) {
  const DemoStation& d = demo();
  const WorldOptions options;
  int tracker_kinds[3] = {0, 0, 0}, frames = 0, visible = 0;
  double marker_error2 = 0.0;
  TimeNs previous_delivery = 0;
  for (const DeviceSample& s : d.world.samples) {
    EXPECT_GE(s.delivered_ns, previous_delivery);  // in delivery order
    previous_delivery = s.delivered_ns;
    EXPECT_NE(s.kind, SampleKind::tumour);  // the world records frames; the station finds the tumour
    if (s.kind == SampleKind::ultrasound_frame) {
      EXPECT_EQ(s.delivered_ns - s.measured_ns, options.ultrasound_delay_ns);
      EXPECT_EQ(s.frame_index, frames);
      visible += d.world.frames[static_cast<std::size_t>(s.frame_index)].tumour_visible ? 1 : 0;
      ++frames;
      continue;
    }
    EXPECT_EQ(s.delivered_ns - s.measured_ns, 10 * kNsPerMs);  // devices.tracker.latency_ms
    ++tracker_kinds[static_cast<int>(s.kind)];
    if (s.kind == SampleKind::respiratory) {
      const double truth_m = BreathingGeometry{}.marker_rest_m[2] + marker_displacement_m(options, s.measured_ns);
      marker_error2 += (s.point_m[2] - truth_m) * (s.point_m[2] - truth_m);
    }
  }
  EXPECT_EQ(tracker_kinds[0], 600);  // 60 Hz over [0, 10 s]
  EXPECT_EQ(tracker_kinds[1], 600);
  EXPECT_EQ(tracker_kinds[2], 600);
  EXPECT_EQ(frames, 201);  // 20 Hz over [0, 10 s]
  EXPECT_EQ(d.world.frames.size(), 201u);
  EXPECT_EQ(visible, frames);  // the probe's fan keeps the tumour in its plane
  const double marker_std_m = std::sqrt(marker_error2 / tracker_kinds[2]);
  std::printf("[ station  ] marker noise %.3f mm (per axis)\n", 1e3 * marker_std_m);
  EXPECT_NEAR(marker_std_m, 0.25e-3, 0.03e-3);  // devices.tracker.position_noise_m; 600 draws
  // Breathing reaches the tumour: the full-order truth moves it by millimetres.
  double low = 1e9, high = -1e9;
  for (const Point3& p : d.world.tumour_truth_m) low = std::min(low, p[2]), high = std::max(high, p[2]);
  std::printf("[ station  ] tumour motion (z) in the truth: %.2f mm peak to peak\n", 1e3 * (high - low));
  EXPECT_GT(high - low, 2e-3);
}

// The scene's needle in the world (coupled to the full-order liver) and in the station's loop
// (coupled to its reduced liver): placed straight outside the liver at the start, it pushes the
// capsule up to its puncture force (1 N) and punctures it once in both; the true tip bends
// away from the holder's straight line; the modelled tip is scored against the true bent tip.
TEST(StationRun, TheNeedlePushesAndPuncturesTheCapsuleInTheWorldAndInTheLoop) {
  const DemoStation& d = demo();
  ASSERT_TRUE(d.loop.has_needle());
  const SimulatedWorld& w = d.world;
  ASSERT_EQ(w.needle_tip_truth_m.size(), 10 * w.tumour_truth_m.size());  // a tip per 1 ms tick, a tumour per 10 ms step
  const Eigen::Vector3d straight_start = w.needle_start_m;
  EXPECT_LT((w.needle_tip_at(0) - straight_start).norm(), 1e-9);  // placed straight at the true marker pose
  // The layers of demo.yaml: the capsule where the path enters; the start is outside it.
  const TissueLayer& capsule = d.scene.needle->interaction.layers[0];
  const Eigen::Vector3d surface{capsule.surface_point_m[0], capsule.surface_point_m[1], capsule.surface_point_m[2]};
  const Eigen::Vector3d normal{capsule.outward_normal[0], capsule.outward_normal[1], capsule.outward_normal[2]};
  EXPECT_GT((straight_start - surface).dot(normal), 1e-3);
  double bend_m = 0.0;
  for (TimeNs t = 0; t <= kDuration; t += 10 * kNsPerMs)
    bend_m = std::max(
        bend_m,
        (w.needle_tip_at(t) - (w.needle_start_m + 1e-9 * static_cast<double>(t) * w.needle_velocity_m_s)).norm());
  const StationReplay replay = replay_station(d.loop, observed(), kDuration, true).value();
  double loop_peak_n = 0.0;
  int loop_punctures = 0;
  for (const TickRecord& t : replay.ticks)
    loop_peak_n = std::max(loop_peak_n, t.tip_force_n), loop_punctures = std::max(loop_punctures, t.punctures);
  const PredictionErrors e = prediction_errors(w, replay.ticks, d.loop.options.display_latency_ns, kSettled);
  std::printf(
      "[ station  ] needle: truth %d punctures, tip force peak %.3f N, bend up to %.2f mm; loop %d punctures, peak "
      "%.3f N; "
      "modelled tip vs true tip %.2f mm RMS\n",
      w.needle_punctures, w.needle_peak_tip_force_n, 1e3 * bend_m, loop_punctures, loop_peak_n,
      1e3 * e.needle_tip_rms_m);
  EXPECT_EQ(w.needle_punctures, 1);
  EXPECT_EQ(loop_punctures, 1);
  EXPECT_NEAR(w.needle_peak_tip_force_n, capsule.puncture_force_n, 0.05 * capsule.puncture_force_n);
  EXPECT_NEAR(loop_peak_n, capsule.puncture_force_n, 0.05 * capsule.puncture_force_n);
  EXPECT_GT(bend_m, 1e-3);  // the tissue bends the true needle: its tip is not the holder's straight tip
  // 1.64 mm as measured (docs/station.md: the aim is 1.5 mm); the bound keeps it from
  // growing unseen.
  EXPECT_LT(e.needle_tip_rms_m, 2.0e-3);
}

/// The modelled tip's RMS distance from the true one on a patient as the scene says (its
/// tissue as stiff, its diaphragm as the marker map says, a tracker without noise or latency),
/// the needle's point forces keeping `own_share` on their nodes in the full-order livers; and
/// the most elements the patient's liver had inverted at once.
struct ModelFormError {
  double tip_rms_m = 0.0;
  int peak_inverted_elements = 0;
};

ModelFormError model_form_error(double own_share) {
  WorldOptions patient;
  patient.truth_stiffness_factor = 1.0;
  patient.diaphragm_gain = 1.0;
  patient.diaphragm_lag_ns = 0;
  const DemoStation d(
      kDuration,
      [own_share](Scene& scene) {
        scene.devices.tracker.latency_ms = 0.0;
        scene.devices.tracker.position_noise_m = 0.0;
        scene.devices.tracker.rotation_noise_rad = 0.0;
        scene.needle->point_force_own_share = own_share;
      },
      patient);
  const std::vector<DeviceSample> samples = observed_recording(d.world, TumourObserverOptions{});
  const StationReplay replay = replay_station(d.loop, samples, kDuration, true).value();
  const PredictionErrors e = prediction_errors(d.world, replay.ticks, d.loop.options.display_latency_ns, kSettled);
  return {e.needle_tip_rms_m, d.world.needle_peak_inverted_elements};
}

// The needle's model-form error: on a patient as the scene says, the modelled tip differs from
// the true one only as the loop's reduced liver (16 modes, the static compliance they miss
// within 15 mm, 0.5 mm/N about each point) differs from the full order. With each needle force
// on one node the patient's liver inverts elements under it (1 N on 1-1.5 cm elements) and the
// tips part by millimetres as the needle goes deeper; with the demo's share (half of a force on
// its node, half on its neighbours) no element inverts and the tips stay within a millimetre.
TEST(StationRun, OnAPatientAsTheSceneSaysTheModelledTipFollowsTheTrueOne) {
  const double demo_share = demo().scene.needle->point_force_own_share;
  const ModelFormError spread = model_form_error(demo_share), alone = model_form_error(1.0);
  std::printf(
      "[ station  ] patient as the scene: modelled tip vs true tip %.2f mm RMS with each force spread (own share %.2f; "
      "%d elements inverted at most), %.2f mm on its node alone (%d inverted)\n",
      1e3 * spread.tip_rms_m, demo_share, spread.peak_inverted_elements, 1e3 * alone.tip_rms_m,
      alone.peak_inverted_elements);
  EXPECT_LT(demo_share, 1.0);
  EXPECT_EQ(spread.peak_inverted_elements, 0);
  EXPECT_LT(spread.tip_rms_m, 1.0e-3);
  EXPECT_GT(alone.peak_inverted_elements, 0);
  EXPECT_GT(alone.tip_rms_m, 2.0 * spread.tip_rms_m);
}

TEST(StationRun, TheTumourFoundInTheFramesIsWithinAMillimetreOfTheTruth) {
  const DemoStation& d = demo();
  ObserverCounts counts;
  const std::vector<DeviceSample> samples = observed_recording(d.world, TumourObserverOptions{}, &counts);
  double error2[3] = {0.0, 0.0, 0.0}, worst_m = 0.0;
  int points = 0;
  for (const DeviceSample& s : samples) {
    if (s.kind != SampleKind::tumour) continue;
    EXPECT_EQ(s.delivered_ns - s.measured_ns, WorldOptions{}.ultrasound_delay_ns);  // delivered with its frame
    const Point3 truth = d.world.tumour_at(s.measured_ns);
    double e2 = 0.0;
    for (std::size_t c = 0; c < 3; ++c) {
      const double e = s.point_m[static_cast<Eigen::Index>(c)] - truth[c];
      error2[c] += e * e;
      e2 += e * e;
    }
    worst_m = std::max(worst_m, std::sqrt(e2));
    ++points;
  }
  const double rms_m = std::sqrt((error2[0] + error2[1] + error2[2]) / points);
  std::printf(
      "[ station  ] %lld frames, %d tumour points (%lld dropped): RMS %.3f mm (x %.3f, y %.3f, z %.3f), worst %.3f "
      "mm\n",
      static_cast<long long>(counts.frames), points,
      static_cast<long long>(counts.dropped_no_detection + counts.dropped_no_pose), 1e3 * rms_m,
      1e3 * std::sqrt(error2[0] / points), 1e3 * std::sqrt(error2[1] / points), 1e3 * std::sqrt(error2[2] / points),
      1e3 * worst_m);
  EXPECT_EQ(counts.frames, 201);
  EXPECT_EQ(counts.observations, points);
  EXPECT_GE(points, 190);  // nearly every frame gives a confident detection
  EXPECT_LT(rms_m, 1e-3);
  EXPECT_LT(worst_m, 2.5e-3);
}

TEST(StationRun, RunsTheLoopAt1kHzFor10sWithoutDeadlineMisses) {
  const DemoStation& d = demo();
  StationRunOptions options;
  options.duration_ns = kDuration;
  options.miss_threshold_ns = 2 * kNsPerMs;
  options.realtime = {d.scene.station.realtime_core, d.scene.station.realtime_priority,
                      false};  // no mlockall in a test process
  options.io_core = d.scene.station.io_core;
  testing::CoreStallWitness witness(options.realtime.core, options.realtime.priority + 1);
  testing::CoreStallWitness io_witness(options.io_core, 1);  // above the I/O thread (not real-time)
  const StationRun run = run_station(d.loop, d.world, options).value();
  const testing::CoreStalls host = witness.stop(), io_host = io_witness.stop();
  const StepStatistics& s = run.steps;
  std::printf(
      "[ station  ] %lld ticks: step median %.1f us, p99 %.1f us, p99.9 %.1f us, max %.1f us; lateness jitter %.1f us, "
      "p99 %.1f us, "
      "p99.99 %.1f us, max %.1f us; %lld ticks over 1 ms late, %lld over 2 ms\n",
      static_cast<long long>(s.ticks), s.median_us, s.p99_us, s.p999_us, s.max_us, s.jitter_us, s.lateness_p99_us,
      s.lateness_p9999_us, s.max_lateness_us, static_cast<long long>(s.late_over_1ms),
      static_cast<long long>(s.deadline_misses));
  for (const SetupStep& step : run.realtime_setup)
    std::printf("[ station  ] %s: %s\n", step.name.c_str(), outcome_name(step.outcome));
  std::printf(
      "[ station  ] the host stalled core %d %lld times, %.1f ms in all, longest %.1f ms (witness at SCHED_FIFO %d: "
      "%s)\n",
      options.realtime.core, static_cast<long long>(host.stalls_ns.size()),
      1e-6 * static_cast<double>(host.stalled_ns()), 1e-6 * static_cast<double>(host.longest_ns()),
      options.realtime.priority + 1, host.witnessed ? "applied" : "not applied");
  std::printf(
      "[ station  ] and the I/O core %d %lld times, %.1f ms in all, longest %.1f ms; %lld samples reached after the "
      "loop\n",
      options.io_core, static_cast<long long>(io_host.stalls_ns.size()),
      1e-6 * static_cast<double>(io_host.stalled_ns()), 1e-6 * static_cast<double>(io_host.longest_ns()),
      static_cast<long long>(run.samples_after_loop));
  const PredictionErrors e = prediction_errors(d.world, run.ticks, d.loop.options.display_latency_ns, kSettled);
  std::printf(
      "[ station  ] real time, assimilated: tumour now %.3f mm, ahead %.3f mm, needle tip %.3f mm RMS; %lld outputs "
      "read\n",
      1e3 * e.tumour_now_rms_m, 1e3 * e.tumour_ahead_rms_m, 1e3 * e.needle_tip_rms_m,
      static_cast<long long>(run.outputs_read));
  EXPECT_GE(s.ticks + s.skipped_ticks, 10000);  // every deadline of 10 s at 1 kHz was ticked or counted
  // The loop keeps every deadline its host leaves it: it passes over only the deadlines that
  // fell in the host's stalls of its core (at most 100 besides), and a tick is 2 ms late only
  // after a stall the witness saw (longer than half its period; one late tick per stall, and
  // 2 besides). Its jitter is the host's stalls' and at most 150 us of its own: the standard
  // deviation of the lateness is bounded by 150 us and every stall (plus a period) counted as a
  // late tick. On a quiet host that is no miss, 9500 ticks or more and a jitter under 150 us.
  // The witnesses watch from before the run's set-up to after its end, which can only loosen these bounds.
  const TimeNs period = d.loop.options.tick_period_ns;
  const TimeNs stalled_ns = host.witnessed ? host.stalled_ns() : 0;
  EXPECT_LE(s.skipped_ticks, stalled_ns / period + 100);
  EXPECT_LE(s.deadline_misses, host.witnessed ? host.longer_than(period / 2) + 2 : 0);
  double stalls_us2 = 0.0;  // of the witnessed stalls, each with a period on top
  for (const TimeNs stall_ns : host.witnessed ? host.stalls_ns : std::vector<TimeNs>{})
    stalls_us2 += std::pow(1e-3 * static_cast<double>(stall_ns + period), 2);
  EXPECT_LE(s.jitter_us,
            std::sqrt(150.0 * 150.0 + stalls_us2 / static_cast<double>(std::max<std::int64_t>(s.ticks, 1))));
  // Every sample but the last frame (delivered after the run) went through the I/O thread,
  // frames as their tumour points; to the loop, but those due in the I/O core's last stall
  // (at most its longest, and the tumour tracker's 20 ms besides).
  EXPECT_EQ(run.samples_pushed + run.samples_after_loop, static_cast<std::int64_t>(observed().size()) - 1);
  EXPECT_EQ(run.observer.frames, 200);
  const TimeNs io_lag_ns = io_host.longest_ns() + 20 * kNsPerMs;
  EXPECT_LE(run.samples_after_loop, std::count_if(observed().begin(), observed().end(), [&](const DeviceSample& x) {
              return x.delivered_ns > kDuration - io_lag_ns && x.delivered_ns <= kDuration;
            }));
  EXPECT_GT(run.outputs_read, s.ticks / 10);  // the display side read outputs throughout
  // The loop ran on the real samples (the replay below is the accuracy check), when its host
  // let it tick: with a fifth of its ticks on a stalled host the estimate was 1.7 mm.
  if (s.ticks >= 9500) {
    EXPECT_LT(e.tumour_now_rms_m, 1.5e-3);
  }
}

TEST(StationRun, ReplayingTheSameRecordingTwiceIsBitwiseIdentical) {
  const DemoStation& d = demo();
  const TimeNs duration = 3 * kNsPerSecond;
  const StationReplay first = replay_station(d.loop, observed(), duration, true).value();
  const StationReplay second = replay_station(d.loop, observed(), duration, true).value();
  EXPECT_EQ(first.output_hash, second.output_hash);
  EXPECT_TRUE(same_records(first.ticks, second.ticks));
  EXPECT_EQ(first.ticks.size(), static_cast<std::size_t>(duration / kNsPerMs) + 1);
  // The hash sees a change of one respiratory marker sample by 1 um.
  std::vector<DeviceSample> changed = observed();
  for (DeviceSample& s : changed)
    if (s.kind == SampleKind::respiratory && s.measured_ns >= kNsPerSecond) {
      s.point_m[2] += 1e-6;
      break;
    }
  const StationReplay third = replay_station(d.loop, changed, duration, true).value();
  EXPECT_NE(first.output_hash, third.output_hash);
}

// The tumour points come from the frames (as the I/O thread finds them).
TEST(StationRun, AssimilationKeepsTheTumourWithin1MillimetreRms) {
  const DemoStation& d = demo();
  const StationReplay with = replay_station(d.loop, observed(), kDuration, true).value();
  const StationReplay without = replay_station(d.loop, observed(), kDuration, false).value();
  const TimeNs latency = d.loop.options.display_latency_ns;
  const PredictionErrors a = prediction_errors(d.world, with.ticks, latency, kSettled);
  const PredictionErrors o = prediction_errors(d.world, without.ticks, latency, kSettled);
  std::printf(
      "[ station  ] tumour RMS over %d liver steps: now %.3f mm (without %.3f mm), at +%lld ms %.3f mm (without %.3f "
      "mm)\n",
      a.steps, 1e3 * a.tumour_now_rms_m, 1e3 * o.tumour_now_rms_m, static_cast<long long>(latency / kNsPerMs),
      1e3 * a.tumour_ahead_rms_m, 1e3 * o.tumour_ahead_rms_m);
  EXPECT_EQ(a.steps, 901);
  EXPECT_LE(a.tumour_now_rms_m, 1e-3);
  EXPECT_LE(a.tumour_ahead_rms_m, 1e-3);
  EXPECT_LT(a.tumour_now_rms_m, 0.8 * o.tumour_now_rms_m);
  EXPECT_LT(a.tumour_ahead_rms_m, 0.8 * o.tumour_ahead_rms_m);
}

/// The demo scene with every topic renamed under site_c/, written to a temporary file (its
/// URDF path made absolute); the file's path.
std::string renamed_demo_scene() {
  const std::filesystem::path folder = std::filesystem::path(testing::example_scene_path("demo.yaml")).parent_path();
  const std::string urdf = "../../../calibration/urdf/station.urdf";
  std::string text = testing::edited(testing::demo_text(), urdf, (folder / urdf).lexically_normal().string());
  for (const char* name : {"tool_pose", "ultrasound_frame", "target_prediction", "deformed_surface", "needle_state",
                           "needle_force", "station_health"})
    text = testing::edited(text, std::string(": nav/") + name, std::string(": site_c/") + name);
  const std::string path = testing::temporary_path("station_demo_site_c.yaml");
  std::ofstream(path) << text;
  return path;
}

TEST(StationRun, NavstationRunsASceneAndPrintsItsSummary) {
  const std::string svg = testing::temporary_path("station_demo.svg");
  const std::string images = testing::temporary_path("station_demo_images");
  // The demo scene on renamed topics: navview, run alongside, only draws (and writes images)
  // if it reads the topics by the scene's names too.
  const std::string scene = renamed_demo_scene();
  // Under AddressSanitizer, Debian's libfastrtps 2.9 deletes its statistics writers and readers
  // through a base of another size (new-delete-type-mismatch, all frames inside libfastrtps);
  // test programs never see it because the allocation guard replaces operator new/delete, but
  // navstation and navview do. The option turns that one check off; it does nothing elsewhere.
  const testing::CommandRun run = testing::run_command(
      "ASAN_OPTIONS=new_delete_type_mismatch=0 " + testing::executable_path("navstation") + " --scene " + scene +
      " --seconds 2 --domain 151 --plot " + svg + " --images " + images + " 2>&1");
  std::printf("%s", run.output.c_str());
  EXPECT_EQ(run.exit_code, 0);
  for (const char* line :
       {"prediction error against the full-order truth", "tumour now", "tumour at +50 ms", "step time over",
        "DDS (domain 151;", "deformed surface (565 vertices)", "error plot: ", "navview: "})
    EXPECT_NE(run.output.find(line), std::string::npos) << "missing: " << line;
  // This program shares the host with other tests and runs under the sanitizers too: the
  // budgets are generous (a twentieth of the 2001 ticks more than 5 ms late, three quarters of
  // the 40 frames through DDS); the real figures are printed above.
  EXPECT_LE(testing::number_after(run.output, "deadline misses (> 5 ms late): "), 100.0);
  EXPECT_GE(testing::number_after(run.output, "ultrasound: "), 30.0);
  // The needle's forces, one per tick of the needle model (it steps from the first needle pose
  // on: within 0.1 s natively, 0.3-0.7 s under ThreadSanitizer), best effort: a lagging output
  // thread may drop some. Native runs give about 1,960 of 2,001, none dropped.
  const double forces = testing::number_after(run.output, "needle forces at the loop rate: ");
  const double forces_dropped = testing::number_after(run.output, " published, ");
  EXPECT_GE(forces + forces_dropped, 1000.0);
  EXPECT_LE(forces + forces_dropped, 2001.0);
  EXPECT_GE(forces, 0.5 * (forces + forces_dropped));
  const std::string plot = testing::file_text(svg);
  EXPECT_NE(plot.find("<svg"), std::string::npos);
  EXPECT_NE(plot.find("<polyline"), std::string::npos);
  // navview ran alongside and wrote composites of the station's topics (PNG signature).
  const std::string png = testing::file_text(images + "/navview_000001.png");
  ASSERT_GE(png.size(), 8u);
  EXPECT_EQ(png.substr(1, 3), "PNG");
  std::remove(svg.c_str());
  std::remove(scene.c_str());
  std::filesystem::remove_all(images);
}

TEST(StationRun, NavviewRenamesOnlyTopicsItKnows) {
  // --topic DEFAULT=NAME: DEFAULT must be a topic's default name and NAME must not be empty.
  for (const char* topic : {"nav/bogus=site_c/bogus", "nav/needle_state=", "needle_state=site_c/needle_state"}) {
    const testing::CommandRun run = testing::run_command(testing::executable_path("navview") +
                                                         " --headless --duration-s 0.1 --topic " + topic + " 2>&1");
    EXPECT_EQ(run.exit_code, 2) << topic << "\n" << run.output;
    EXPECT_NE(run.output.find("--topic DEFAULT=NAME"), std::string::npos) << run.output;
  }
}

}  // namespace
}  // namespace nav::station
