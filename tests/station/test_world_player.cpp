// The simulated patient of a long run: its needle stops where the world says, and the player
// goes on past the recording by repeating its last period (navdevice sim's soak runs). A short
// world (1 s breaths, 0.5 s sweeps: a 1 s period) is played for twice its length through a
// real DDS writer to a reader on loopback: every stream stays in time and sequence order, and
// each repeated pose, frame stamp and truth is the recording's one period earlier.
#include <gtest/gtest.h>

#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <map>
#include <memory>
#include <thread>
#include <vector>

#include "demo_station.hpp"
#include "nav/dds/dds_node.hpp"
#include "nav/station/station_dds.hpp"
#include "nav/station/tracker_registration.hpp"
#include "nav/station/world_player.hpp"

namespace nav::station {
namespace {

constexpr std::uint32_t kPlayerDomain = 214;
constexpr TimeNs kRecorded = 3 * kNsPerSecond;
constexpr TimeNs kPlayed = 6 * kNsPerSecond;

WorldOptions short_world() {
  WorldOptions options;
  options.duration_ns = kRecorded;
  options.breathing_period_s = 1.0;
  options.probe_sweep_period_s = 0.5;
  options.needle_travel_m = 0.005;  // stops after 1 s at 5 mm/s
  return options;
}

/// Every frame's stamp and sequence number, without its pixels (written by the listener,
/// read by the test once count() stops growing).
class FrameStamps final : public dds::SampleSink<dds::UltrasoundFrame> {
 public:
  dds::SampleFault offer(const dds::UltrasoundFrame& frame) noexcept override {
    const std::size_t n = count_.load(std::memory_order_relaxed);
    if (n == stamps_.size()) return dds::SampleFault::buffer_full;
    stamps_[n] = {frame.source_time_ns, frame.sequence_number};
    count_.store(n + 1, std::memory_order_release);
    return dds::SampleFault::none;
  }
  std::size_t count() const noexcept { return count_.load(std::memory_order_acquire); }
  const std::pair<TimeNs, std::uint64_t>& operator[](std::size_t i) const noexcept { return stamps_[i]; }

 private:
  std::array<std::pair<TimeNs, std::uint64_t>, 1024> stamps_{};
  std::atomic<std::size_t> count_{0};
};

TEST(SimulatedWorld, TheNeedleStopsAfterItsTravelAndThePeriodHoldsWholeBreathsAndSweeps) {
  EXPECT_EQ(world_period_ns(WorldOptions{}), 12 * kNsPerSecond);  // 4 s breaths, 3 s sweeps
  EXPECT_EQ(world_period_ns(short_world()), kNsPerSecond);
  WorldOptions odd = short_world();
  odd.breathing_period_s = 0.3;
  odd.probe_sweep_period_s = 0.2;
  EXPECT_EQ(world_period_ns(odd), 600 * kNsPerMs);

  SimulatedWorld world;
  world.needle_start_m = {0.01, 0.02, 0.03};
  world.needle_velocity_m_s = {0.0, -0.005, 0.0};
  world.needle_stop_ns = kNsPerSecond;
  EXPECT_NEAR(world.needle_tip_at(500 * kNsPerMs)[1], 0.0175, 1e-12);
  EXPECT_NEAR(world.needle_tip_at(kNsPerSecond)[1], 0.015, 1e-12);
  EXPECT_NEAR(world.needle_tip_at(5 * kNsPerSecond)[1], 0.015, 1e-12);
  EXPECT_TRUE(world.needle_marker_at(2 * kNsPerSecond)
                  .position_m.isApprox(world.needle_marker_at(9 * kNsPerSecond).position_m, 1e-15));
  EXPECT_FALSE(world.needle_marker_at(0).position_m.isApprox(world.needle_marker_at(kNsPerSecond).position_m, 1e-6));
}

TEST(WorldPlayer, PlaysOnPastItsRecordingByRepeatingItsLastPeriod) {
  Scene scene = load_scene(testing::example_scene_path("demo.yaml")).value();
  const StationLiver liver = make_station_liver(scene).value();
  const WorldOptions options = short_world();
  auto world = simulate_world(liver, scene, BreathingGeometry{}, options);
  ASSERT_TRUE(world.ok()) << world.error().describe();
  const TimeNs period_ns = world_period_ns(options);

  auto poses = std::make_unique<dds::RingSink<dds::ToolPose, 4096>>();
  auto truths = std::make_unique<dds::RingSink<dds::GroundTruth, 1024>>();
  auto frames = std::make_unique<FrameStamps>();
  auto reader = make_station_node(kPlayerDomain, "world_player_reader");
  auto writer = make_station_node(kPlayerDomain, "world_player_writer", {}, {}, Role::devices);
  ASSERT_TRUE(reader.ok() && writer.ok());
  dds::DdsNode& in = *reader.value();
  dds::DdsNode& out = *writer.value();
  ASSERT_TRUE(in.subscribe(*poses).ok() && in.subscribe(*frames).ok() && in.subscribe(*truths).ok());
  ASSERT_TRUE(out.advertise<dds::ToolPose>().ok() && out.advertise<dds::UltrasoundFrame>().ok() &&
              out.advertise<dds::GroundTruth>().ok());
  for (dds::Topic topic : {dds::Topic::tool_pose, dds::Topic::ultrasound_frame, dds::Topic::ground_truth})
    ASSERT_TRUE(out.wait_for_match(topic, 1, 5 * kNsPerSecond));

  const TrackerSettings& t = scene.devices.tracker;
  WorldPlayer player(world.value(), true,
                     simulated_tracker(t.tools, t.tracker_from_reference, scene_reference_from_model(scene).value()));
  player.repeat_last(period_ns);
  MonotonicClock clock;
  for (TimeNs now_ns = 0; now_ns <= kPlayed; now_ns += 10 * kNsPerMs) {
    player.play_until(now_ns, &out, clock);
    clock.sleep_until_ns(clock.now_ns() + kNsPerMs);
  }
  EXPECT_FALSE(player.finished());
  ASSERT_TRUE(out.wait_for_acknowledgments(5 * kNsPerSecond));            // the truths (reliable)
  for (std::size_t seen = 0; seen != frames->count() + poses->size();) {  // the best-effort poses and frames
    seen = frames->count() + poses->size();
    std::this_thread::sleep_for(std::chrono::milliseconds(200));
  }

  // Poses: per tool, in time and sequence order; each past the recording is the one a period before.
  std::map<std::uint32_t, std::map<TimeNs, dds::ToolPose>> by_tool;
  const auto is_reference = [&](const dds::ToolPose& pose) {
    return t.tools.reference && pose.tool_id == *t.tools.reference;
  };
  std::uint64_t last_sequence = 0;  // a reference pose goes with its respiratory sample's number
  std::size_t pose_count = 0, repeated = 0;
  for (dds::ToolPose pose; poses->try_pop(pose); ++pose_count) {
    auto& track = by_tool[pose.tool_id];
    if (!track.empty()) {
      EXPECT_GT(pose.source_time_ns, track.rbegin()->first) << "tool " << pose.tool_id;
    }
    if (!is_reference(pose)) {
      if (pose_count > 0) {
        EXPECT_GT(pose.sequence_number, last_sequence);
      }
      last_sequence = pose.sequence_number;
    }
    track[pose.source_time_ns] = pose;
  }
  for (const auto& [tool, track] : by_tool)
    for (const auto& [time_ns, pose] : track) {
      if (time_ns < kRecorded) continue;
      const auto earlier = track.find(time_ns - period_ns);
      ASSERT_NE(earlier, track.end()) << "tool " << tool << " at " << time_ns;
      for (std::size_t c = 0; c < 3; ++c) EXPECT_EQ(pose.position_m[c], earlier->second.position_m[c]);
      for (std::size_t c = 0; c < 4; ++c) EXPECT_EQ(pose.orientation_wxyz[c], earlier->second.orientation_wxyz[c]);
      ++repeated;
    }
  const double tracker_poses_per_s = 3.0 * t.rate_hz + (t.tools.reference ? t.rate_hz : 0.0);
  const double expected_poses = tracker_poses_per_s * 1e-9 * static_cast<double>(kPlayed);
  std::printf("%zu poses over %.0f s (expected about %.0f), %zu of them repeats\n", pose_count,
              1e-9 * static_cast<double>(kPlayed), expected_poses, repeated);
  EXPECT_NEAR(static_cast<double>(pose_count), expected_poses, 0.02 * expected_poses);
  EXPECT_NEAR(static_cast<double>(repeated), expected_poses / 2.0, 0.02 * expected_poses);

  // Frames: in time and sequence order at the scanner's rate over the whole played time.
  const FrameStamps& f = *frames;
  ASSERT_GT(f.count(), 0u);
  for (std::size_t i = 1; i < f.count(); ++i) {
    EXPECT_GT(f[i].first, f[i - 1].first);
    EXPECT_GT(f[i].second, f[i - 1].second);
  }
  const double expected_frames = scene.devices.ultrasound.rate_hz * 1e-9 * static_cast<double>(kPlayed);
  EXPECT_NEAR(static_cast<double>(f.count()), expected_frames, 2.0);
  EXPECT_GT(f[f.count() - 1].first, kPlayed - kNsPerSecond);

  // Truths: one per tissue step to the end of play; past the recording, a period before's.
  std::map<TimeNs, dds::GroundTruth> truth;
  for (dds::GroundTruth sample; truths->try_pop(sample);) truth[sample.source_time_ns] = sample;
  EXPECT_EQ(truth.size(), static_cast<std::size_t>(kPlayed / world.value().step_ns + 1));
  for (const auto& [time_ns, sample] : truth) {
    if (time_ns < kRecorded) continue;
    const auto earlier = truth.find(time_ns - period_ns);
    ASSERT_NE(earlier, truth.end());
    for (std::size_t c = 0; c < 3; ++c) {
      EXPECT_EQ(sample.tumour_m[c], earlier->second.tumour_m[c]);
      EXPECT_EQ(sample.needle_tip_m[c], earlier->second.needle_tip_m[c]);
    }
  }
}

}  // namespace
}  // namespace nav::station
