// The running station with its devices on real Fast DDS (loopback and shared memory only, the
// project's network rules): the demo's simulated tracker and B-mode scanner publish from a
// participant of their own on nav/tool_pose and nav/ultrasound_frame; the station's I/O thread
// takes them, finds the tumour in the frames, feeds the real-time loop and publishes its
// outputs (nav/target_prediction, nav/needle_state, nav/station_health) and the deformed liver
// surface it rebuilds from the loop's reduced state (nav/deformed_surface, 20 Hz), which a
// display participant receives: on the surface, the liver's attachments stay at rest and its
// diaphragm region moves as one with the breathing. Then the fault "a DDS peer disappearing": the devices' participant
// is destroyed for 1 s and created again. Checked: the I/O thread sees the writers go and come back; the loop flags the
// needle input (stale, then missing) within 500 ms of the loss (generous) and its outputs are degraded, every output
// stays finite, the health on DDS says so; and the needle input is good again within 1 s of the writers being matched
// again (the figures are printed). Last, the station on a scene that renames every topic: a reader on the scene's names
// gets its outputs, a reader on the default names nothing. The counts are checked against what the run itself did (the
// samples the devices wrote, the ticks the loop ran), never against the wall clock: on a host that stalls the process
// the loop skips ticks and the I/O thread takes fewer poses, and the figures printed say so.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>

#include "demo_station.hpp"
#include "nav/core/health.hpp"
#include "nav/dds/dds_node.hpp"
#include "nav/dds/sample_sink.hpp"
#include "nav/station/display_surface.hpp"
#include "nav/station/station_dds.hpp"

namespace nav::station {
namespace {

constexpr TimeNs kDuration = 5 * kNsPerSecond;
constexpr TimeNs kSettled = 1 * kNsPerSecond;

using nav::testing::DemoStation;

const DemoStation& demo() {
  static const DemoStation built(kDuration);
  return built;
}

/// A display on `domain_id`: it takes the station's predictions, needle, health and surfaces
/// on the topics named by `names` (empty entries: the default names).
struct Display {
  std::unique_ptr<dds::DdsNode> node;
  std::unique_ptr<dds::RingSink<dds::TargetPrediction, 2048>> predictions =
      std::make_unique<dds::RingSink<dds::TargetPrediction, 2048>>();
  std::unique_ptr<dds::RingSink<dds::NeedleState, 512>> needle =
      std::make_unique<dds::RingSink<dds::NeedleState, 512>>();
  std::unique_ptr<dds::RingSink<dds::StationHealth, 128>> health =
      std::make_unique<dds::RingSink<dds::StationHealth, 128>>();
  std::unique_ptr<dds::RingSink<dds::DeformedSurface, 128>> surfaces =
      std::make_unique<dds::RingSink<dds::DeformedSurface, 128>>();
  explicit Display(std::uint32_t domain_id, const dds::TopicNames& names = {}) {
    node = make_station_node(domain_id, "nav_test_display", names).value();
    EXPECT_TRUE(node->subscribe(*predictions).ok());
    EXPECT_TRUE(node->subscribe(*needle).ok());
    EXPECT_TRUE(node->subscribe(*health).ok());
    EXPECT_TRUE(node->subscribe(*surfaces).ok());
  }
};

/// Takes every sample out of `sink` (into `last`); how many there were.
template <class Sink, class Sample>
int drain(Sink& sink, Sample& last) {
  int count = 0;
  while (sink.try_pop(last)) ++count;
  return count;
}

/// What the loop gave a run's displays: one prediction now and one ahead and one needle state
/// per liver step, one health sample per 100 ms of ticks run.
struct ExpectedOutputs {
  int liver_steps = 0;
  int health = 0;
  std::int64_t pushed() const { return 3 * liver_steps + health; }
};

ExpectedOutputs expected_outputs(const StationRun& run, const DdsRunOptions& options, TimeNs tick_period_ns) {
  ExpectedOutputs e;
  for (const TickRecord& t : run.ticks) e.liver_steps += t.time_ns == t.tissue_time_ns ? 1 : 0;
  e.health = static_cast<int>(static_cast<TimeNs>(run.ticks.size()) / (options.health_period_ns / tick_period_ns));
  return e;
}

/// Reliable delivery of `expected` samples: all of them, or nearly (5 %, at least one, may be
/// replaced by their newer ones while a stalled host holds the reader back), never more.
void expect_delivered(int received, int expected, const char* what) {
  EXPECT_LE(received, expected) << what;
  EXPECT_GE(received, expected - std::max(1, expected / 20)) << what;
}

/// Best-effort delivery of `written` samples: at least `share` of them (keep-last history: a
/// newer sample of a stream replaces one its reader has not taken yet), never more.
void expect_arrived(std::int64_t arrived, std::int64_t written, double share, const char* what) {
  EXPECT_LE(arrived, written) << what;
  EXPECT_GE(static_cast<double>(arrived), share * static_cast<double>(written)) << what;
}

/// Poses: one keep-last history per tool, 60 Hz each: at least 90 % arrive.
constexpr double kPosesArriving = 0.9;
/// Frames: a history of 2 at 20 Hz, so a stall of the process longer than 100 ms loses the
/// older frames of the burst the devices then write: at least two thirds arrive.
constexpr double kFramesArriving = 2.0 / 3.0;

StationRunOptions dds_options(const DemoStation& d, std::uint32_t domain_id) {
  StationRunOptions options;
  options.duration_ns = kDuration;
  options.miss_threshold_ns = 100 * kNsPerMs;
  options.realtime = {d.scene.station.realtime_core, d.scene.station.realtime_priority,
                      false};  // no mlockall in a test process
  options.io_core = d.scene.station.io_core;
  options.dds = DdsRunOptions{};
  options.dds->domain_id = domain_id;
  return options;
}

bool finite(const Point3& p) { return std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]); }

constexpr std::uint32_t kOutboxOverrun = static_cast<std::uint32_t>(HealthFlag::buffer_overrun);
constexpr std::uint32_t kInputLost =
    static_cast<std::uint32_t>(HealthFlag::stale_input) | static_cast<std::uint32_t>(HealthFlag::missing_input);

/// The largest distance between a surface vertex and its rest position, over `vertices`,
/// and the displacement of the first of them.
struct VertexMotion {
  double spread_m = 0.0;  ///< largest difference between the vertices' displacements
  Eigen::Vector3d first_m = Eigen::Vector3d::Zero();
};

VertexMotion motion_of(const dds::DeformedSurface& s, const DisplaySurface& surface,
                       const std::vector<std::size_t>& vertices) {
  VertexMotion m;
  for (std::size_t k = 0; k < vertices.size(); ++k) {
    const std::size_t v = vertices[k];
    Eigen::Vector3d u;
    for (int c = 0; c < 3; ++c)
      u[c] = static_cast<double>(s.vertex_positions_m[v][static_cast<std::size_t>(c)]) -
             surface.rest_m[v][static_cast<std::size_t>(c)];
    if (k == 0) m.first_m = u;
    m.spread_m = std::max(m.spread_m, (u - m.first_m).norm());
  }
  return m;
}

/// The outputs on a display: every one the loop pushed published, or refused by the outbox
/// while the I/O thread was held up (counted); the published ones received; never more of a
/// kind than the loop gave.
void expect_outputs(const DdsRunReport& r, const ExpectedOutputs& expected, int predictions, int needle_states,
                    int health) {
  EXPECT_EQ(r.outputs_published + static_cast<std::int64_t>(r.outbox_dropped), expected.pushed());
  expect_delivered(predictions + needle_states + health, static_cast<int>(r.outputs_published), "outputs");
  EXPECT_LE(predictions, 2 * expected.liver_steps);
  EXPECT_GT(predictions, 0);
  EXPECT_LE(needle_states, expected.liver_steps);
  EXPECT_GT(needle_states, 0);
  EXPECT_LE(health, expected.health);
  EXPECT_GT(health, 0);
}

/// One surface per period of liver time the loop stepped through (20 Hz), or a period passed
/// over when the I/O thread read no output within it; the display received them.
void expect_surfaces(const StationRun& run, const DdsRunOptions& options, int received) {
  const DdsRunReport& r = *run.dds;
  ASSERT_FALSE(run.ticks.empty());
  const TimeNs periods = run.ticks.back().tissue_time_ns / options.surface_period_ns + 1;
  EXPECT_GT(r.surfaces_published, 0);
  EXPECT_EQ(r.surfaces_published + r.surface_periods_passed_over,
            periods);  // the I/O thread reads the loop's last outputs too
  expect_delivered(received, static_cast<int>(r.surfaces_published), "surfaces");
}

TEST(StationDds, TheDevicesOnDdsFeedTheStationAndItsOutputsReachADisplay) {
  const DemoStation& d = demo();
  const DisplaySurface surface = make_display_surface(d.liver.mesh).value();
  Display display(152);
  StationRunOptions options = dds_options(d, 152);
  options.dds->surface = &surface;
  const StationRun run = run_station(d.loop, d.world, options).value();
  ASSERT_TRUE(run.dds.has_value());
  const DdsRunReport& r = *run.dds;
  std::printf(
      "[ station  ] DDS: %lld poses written, %lld accepted, %lld taken by the I/O thread; %lld of %lld frames "
      "received; writer "
      "to reader: poses median %.0f us, p99 %.0f us, max %.0f us; frames median %.0f us, p99 %.0f us, max %.0f us\n",
      static_cast<long long>(r.poses_written), static_cast<long long>(r.poses_accepted),
      static_cast<long long>(r.poses_received), static_cast<long long>(r.frames_received),
      static_cast<long long>(r.frames_written), r.pose_latency.median_us, r.pose_latency.p99_us, r.pose_latency.max_us,
      r.frame_latency.median_us, r.frame_latency.p99_us, r.frame_latency.max_us);
  std::printf(
      "[ station  ] tumour tracker per frame (I/O thread): median %.2f ms, p99 %.2f ms, max %.2f ms; loop: %lld ticks, "
      "%lld "
      "skipped, max lateness %.1f ms\n",
      1e-3 * run.frame_processing.median_us, 1e-3 * run.frame_processing.p99_us, 1e-3 * run.frame_processing.max_us,
      static_cast<long long>(run.steps.ticks), static_cast<long long>(run.steps.skipped_ticks),
      1e-3 * run.steps.max_lateness_us);
  // 5 s: 3 markers at 60 Hz (delivered from 10 ms) and frames at 20 Hz (from 30 ms), written
  // as they come due until the loop stops (a stall delays them; one at the end leaves the last
  // unwritten). The station's inbox keeps the newest pose of each tool and the I/O thread takes
  // it once per poll (0.5 ms): a stalled I/O thread takes fewer (the loop interpolates over the
  // gap), never more than arrived.
  EXPECT_GE(r.poses_written, 750);
  EXPECT_LE(r.poses_written, 900);
  EXPECT_GE(r.frames_written, 80);
  expect_arrived(r.poses_accepted, r.poses_written, kPosesArriving, "poses");
  expect_arrived(r.frames_received, r.frames_written, kFramesArriving, "frames");
  EXPECT_GT(r.poses_received, 0);
  EXPECT_LE(r.poses_received, r.poses_accepted);
  EXPECT_EQ(run.observer.frames, r.frames_received);
  // The tumour found in 90 % of the frames placed by a probe pose (a stalled I/O thread takes
  // fewer probe poses and leaves some frames without one around their capture time).
  const ObserverCounts& seen = run.observer;
  std::printf(
      "[ station  ] frames: %lld, tumour found in %lld, not found in %lld, %lld without a probe pose around them\n",
      static_cast<long long>(seen.frames), static_cast<long long>(seen.observations),
      static_cast<long long>(seen.dropped_no_detection), static_cast<long long>(seen.dropped_no_pose));
  EXPECT_EQ(seen.observations + seen.dropped_no_detection + seen.dropped_no_pose, seen.frames);
  EXPECT_GE(10 * seen.observations, 9 * (seen.frames - seen.dropped_no_pose));
  EXPECT_GT(seen.observations, 0);
  EXPECT_LT(r.pose_latency.median_us, 2000.0);  // generous: the host runs other test programs
  EXPECT_LT(r.frame_latency.median_us, 5000.0);
  EXPECT_EQ(r.device_gone_ns, -1);
  EXPECT_EQ(r.peer_lost_seen_ns, -1);
  const PredictionErrors e = prediction_errors(d.world, run.ticks, d.loop.options.display_latency_ns, kSettled);
  std::printf(
      "[ station  ] on DDS, assimilated: tumour now %.3f mm, ahead %.3f mm, needle tip %.3f mm RMS (from 1 s of 5 s)\n",
      1e3 * e.tumour_now_rms_m, 1e3 * e.tumour_ahead_rms_m, 1e3 * e.needle_tip_rms_m);
  EXPECT_LT(e.tumour_now_rms_m, 1.2e-3);
  // The display received the predictions (now and ahead, one each per liver step) and the
  // health, as many as the loop's ticks gave.
  const ExpectedOutputs expected = expected_outputs(run, *options.dds, d.loop.options.tick_period_ns);
  dds::TargetPrediction prediction;
  int predictions = 0, ahead = 0;
  while (display.predictions->try_pop(prediction)) {
    ++predictions;
    ahead += prediction.horizon_ns == d.loop.options.display_latency_ns ? 1 : 0;
    EXPECT_TRUE(std::isfinite(prediction.position_m[0]) && std::isfinite(prediction.covariance_m2[0]));
  }
  dds::StationHealth health;
  const int health_samples = drain(*display.health, health);
  auto needle = std::make_unique<dds::NeedleState>();
  const int needle_states = drain(*display.needle, *needle);
  std::printf(
      "[ station  ] display: %d predictions (%d ahead), %d needle states, %d health samples; %lld outputs published, "
      "%llu "
      "dropped by the outbox; the loop: %zu ticks run, %d liver steps\n",
      predictions, ahead, needle_states, health_samples, static_cast<long long>(r.outputs_published),
      static_cast<unsigned long long>(r.outbox_dropped), run.ticks.size(), expected.liver_steps);
  EXPECT_GE(expected.liver_steps, 100);  // at 100 Hz over 5 s: 500 on a host that never stalls
  expect_outputs(r, expected, predictions, needle_states, health_samples);
  EXPECT_LE(ahead, expected.liver_steps);
  EXPECT_GE(2 * ahead, predictions - 1);  // the predictions come in pairs, now and ahead

  // The deformed surface: attachments at rest, the diaphragm region moving as one (the
  // prescribed displacement), by millimetres over a breath.
  std::vector<std::size_t> fixed, diaphragm;
  for (std::size_t v = 0; v < surface.nodes.size(); ++v) {
    const auto is = [&](const std::vector<std::int32_t>& nodes) {
      return std::binary_search(nodes.begin(), nodes.end(), surface.nodes[v]);
    };
    if (is(d.liver.scene.fixed_nodes)) fixed.push_back(v);
    if (is(d.liver.scene.prescribed_nodes)) diaphragm.push_back(v);
  }
  ASSERT_FALSE(fixed.empty());
  ASSERT_FALSE(diaphragm.empty());
  auto sample = std::make_unique<dds::DeformedSurface>();
  int surfaces = 0;
  double fixed_worst_m = 0.0, diaphragm_spread_m = 0.0, lowest_m = 1.0, highest_m = -1.0;
  bool all_finite = true;
  while (display.surfaces->try_pop(*sample)) {
    ++surfaces;
    EXPECT_EQ(sample->surface_id, kLiverSurfaceId);
    ASSERT_EQ(sample->vertex_count, surface.nodes.size());
    for (std::size_t v = 0; v < surface.nodes.size(); ++v)
      for (float x : sample->vertex_positions_m[v]) all_finite = all_finite && std::isfinite(x);
    const VertexMotion at_rest = motion_of(*sample, surface, fixed);
    fixed_worst_m = std::max(fixed_worst_m, at_rest.first_m.norm() + at_rest.spread_m);
    const VertexMotion lifted = motion_of(*sample, surface, diaphragm);
    diaphragm_spread_m = std::max(diaphragm_spread_m, lifted.spread_m);
    lowest_m = std::min(lowest_m, lifted.first_m.z());
    highest_m = std::max(highest_m, lifted.first_m.z());
  }
  std::printf(
      "[ station  ] surface: %d of %lld received (%zu vertices, %lld periods of liver time passed over by the I/O "
      "thread); "
      "reconstruction median %.0f us, p99 %.0f us; attachments within %.2g m of rest, diaphragm vertices within %.2g m "
      "of "
      "one another, lifted %.2f mm peak to peak\n",
      surfaces, static_cast<long long>(r.surfaces_published), surface.nodes.size(),
      static_cast<long long>(r.surface_periods_passed_over), r.surface_reconstruction.median_us,
      r.surface_reconstruction.p99_us, fixed_worst_m, diaphragm_spread_m, 1e3 * (highest_m - lowest_m));
  expect_surfaces(run, *options.dds, surfaces);
  EXPECT_TRUE(all_finite);
  EXPECT_LT(fixed_worst_m, 1e-6);  // float positions of about 0.1 m: ~1e-8 m rounding
  EXPECT_LT(diaphragm_spread_m, 1e-6);
  EXPECT_GT(highest_m - lowest_m, 8e-3);  // the marker's 10 mm breath, mapped 1:1 onto the diaphragm
}

TEST(StationDds, ADevicePeerDisappearingIsFlaggedAndTheStationRecovers) {
  const DemoStation& d = demo();
  Display display(153);
  StationRunOptions options = dds_options(d, 153);
  options.dds->device_outage = PeerOutage{2 * kNsPerSecond, 3 * kNsPerSecond};
  const StationRun run = run_station(d.loop, d.world, options).value();
  const DdsRunReport& r = *run.dds;
  ASSERT_GE(r.device_gone_ns, 2 * kNsPerSecond);
  ASSERT_GE(r.device_back_ns, 3 * kNsPerSecond);
  // The I/O thread sees the writers go (the participant announces its end) and come back.
  ASSERT_GE(r.peer_lost_seen_ns, 0);
  ASSERT_GE(r.peer_back_seen_ns, 0);
  // The loop: the first tick with the needle degraded after the loss, and the first tick with
  // it good again after the return.
  TimeNs flagged_ns = -1, recovered_ns = -1;
  bool flagged_throughout = true, all_finite = true;
  for (const TickRecord& t : run.ticks) {
    all_finite = all_finite && finite(t.tumour_now_m) && finite(t.tumour_ahead_m) && finite(t.needle_tip_m);
    if (flagged_ns < 0 && t.time_ns >= r.device_gone_ns && t.needle_degraded && (t.needle_flags & kInputLost) != 0)
      flagged_ns = t.time_ns;
    if (flagged_ns >= 0 && t.time_ns >= flagged_ns && t.time_ns < r.device_back_ns)
      flagged_throughout = flagged_throughout && t.degraded && t.needle_degraded && (t.needle_flags & kInputLost) != 0;
    if (recovered_ns < 0 && t.time_ns >= r.device_back_ns && !t.needle_degraded && t.needle_flags == 0)
      recovered_ns = t.time_ns;
  }
  std::printf(
      "[ station  ] devices gone at %.3f s: writers seen gone after %.1f ms, needle flagged after %.1f ms; back at "
      "%.3f s: "
      "writers seen after %.1f ms, needle good after %.1f ms; %llu samples lost\n",
      1e-9 * r.device_gone_ns, 1e-6 * (r.peer_lost_seen_ns - r.device_gone_ns), 1e-6 * (flagged_ns - r.device_gone_ns),
      1e-9 * r.device_back_ns, 1e-6 * (r.peer_back_seen_ns - r.device_back_ns),
      1e-6 * (recovered_ns - r.device_back_ns), static_cast<unsigned long long>(r.device_samples_lost));
  EXPECT_LT(r.peer_lost_seen_ns - r.device_gone_ns, 1 * kNsPerSecond);  // generous: the host runs other test programs
  EXPECT_GE(r.peer_back_seen_ns, r.device_back_ns);
  EXPECT_LT(r.peer_back_seen_ns - r.device_back_ns, 2 * kNsPerSecond);
  ASSERT_GE(flagged_ns, 0) << "the needle input was never flagged";
  EXPECT_LT(flagged_ns - r.device_gone_ns, 500 * kNsPerMs);
  EXPECT_TRUE(flagged_throughout) << "the outputs were not degraded for the whole outage";
  EXPECT_TRUE(all_finite);
  ASSERT_GE(recovered_ns, 0) << "the needle input never recovered";
  EXPECT_LT(recovered_ns - r.peer_back_seen_ns, 1 * kNsPerSecond);  // the writers' own return is bounded above
  EXPECT_GT(r.device_samples_lost, 0u);
  // The health on DDS: degraded with a lost input during the outage, and every sample's flags
  // those of the loop's tick at its time (after the return too: all inputs good again where the
  // loop had them so; a host that stalls the loop longer than an input's staleness limit gets
  // that input flagged again, rightly).
  // The needle's age grows through the outage: its newest good sample is older than the outage so far.
  dds::StationHealth health;
  bool degraded_in_outage = false;
  int samples = 0, as_the_loop = 0, aged_in_outage = 0, in_outage = 0;
  TimeNs last_time_ns = 0, last_needle_age_ns = 0;
  constexpr auto kNeedle = static_cast<std::size_t>(dds::StationInput::needle);
  while (display.health->try_pop(health)) {
    const TimeNs health_ns = health.source_time_ns - run.start_ns;  // stamped on the host's clock
    if (health_ns > flagged_ns && health_ns < r.device_back_ns) {
      degraded_in_outage =
          degraded_in_outage || (health.mode == dds::StationMode::degraded && (health.flags & kInputLost) != 0);
      ++in_outage;
      aged_in_outage += health.input_age_ns[kNeedle] >= health_ns - r.device_gone_ns - 50 * kNsPerMs ? 1 : 0;
    }
    last_needle_age_ns = health.input_age_ns[kNeedle];
    const auto tick =
        std::find_if(run.ticks.begin(), run.ticks.end(), [&](const TickRecord& t) { return t.time_ns == health_ns; });
    const bool overrun =
        (health.flags & kOutboxOverrun) != 0;  // the publisher's own flag: its outbox refused an output
    ++samples;
    as_the_loop += tick != run.ticks.end() && tick->health_flags == (health.flags & ~kOutboxOverrun) &&
                           (!overrun || r.outbox_dropped > 0)
                       ? 1
                       : 0;
    last_time_ns = health_ns;
  }
  EXPECT_TRUE(degraded_in_outage);
  EXPECT_GT(in_outage, 0);
  EXPECT_EQ(aged_in_outage, in_outage) << "health samples in the outage whose needle age is younger than the outage";
  EXPECT_GE(last_needle_age_ns, 0);
  EXPECT_LT(last_needle_age_ns, 1 * kNsPerSecond);
  EXPECT_GT(last_time_ns, recovered_ns);
  EXPECT_GT(samples, 0);
  EXPECT_EQ(as_the_loop, samples) << "health samples whose flags are not those of the loop's tick at their time";
}

TEST(StationDds, TheStationRunsOnTheTopicNamesOfItsScene) {
  const DemoStation& d = demo();
  TopicSettings renamed;  // every topic of the scene under site_b/ instead of nav/
  for (std::string* name : {&renamed.poses, &renamed.images, &renamed.predictions, &renamed.surfaces,
                            &renamed.needle_states, &renamed.health})
    name->replace(0, 3, "site_b");
  const dds::TopicNames names = topic_names(renamed);
  const DisplaySurface surface = make_display_surface(d.liver.mesh).value();
  Display on_scene_names(154, names), on_default_names(154);
  StationRunOptions options = dds_options(d, 154);
  options.duration_ns = 1500 * kNsPerMs;
  options.dds->topic_names = names;
  options.dds->surface = &surface;
  const StationRun run = run_station(d.loop, d.world, options).value();
  const DdsRunReport& r = *run.dds;
  // The devices wrote on the scene's names and the station read them there.
  EXPECT_GE(r.poses_written, 180);  // 3 markers at 60 Hz over 1.5 s: 270
  EXPECT_GE(r.frames_written, 20);  // 20 Hz: 30
  expect_arrived(r.poses_accepted, r.poses_written, kPosesArriving, "poses");
  expect_arrived(r.frames_received, r.frames_written, kFramesArriving, "frames");
  dds::TargetPrediction prediction;
  auto needle = std::make_unique<dds::NeedleState>();
  dds::StationHealth health;
  auto deformed = std::make_unique<dds::DeformedSurface>();
  const int received[] = {drain(*on_scene_names.predictions, prediction), drain(*on_scene_names.needle, *needle),
                          drain(*on_scene_names.health, health), drain(*on_scene_names.surfaces, *deformed)};
  const int on_defaults[] = {drain(*on_default_names.predictions, prediction), drain(*on_default_names.needle, *needle),
                             drain(*on_default_names.health, health), drain(*on_default_names.surfaces, *deformed)};
  std::printf(
      "[ station  ] on site_b/: %d predictions, %d needle states, %d health, %d surfaces; on nav/: %d, %d, %d, %d\n",
      received[0], received[1], received[2], received[3], on_defaults[0], on_defaults[1], on_defaults[2],
      on_defaults[3]);
  const ExpectedOutputs expected = expected_outputs(run, *options.dds, d.loop.options.tick_period_ns);
  EXPECT_GE(expected.liver_steps, 15);  // at 100 Hz over 1.5 s: 150 on a host that never stalls
  expect_outputs(r, expected, received[0], received[1], received[2]);
  expect_surfaces(run, *options.dds, received[3]);
  for (int count : on_defaults) EXPECT_EQ(count, 0);
}

}  // namespace
}  // namespace nav::station
