// The boundary's value checks: each kind of bad sample is named by its fault, good samples
// pass, time order is kept per stream and per tool, unknown tools are refused, the pose
// inbox counts the poses it accepts, the counters add up by reason, and
// the health reads as one line of words.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "dds_test_samples.hpp"
#include "nav/core/health.hpp"
#include "nav/dds/health_text.hpp"
#include "nav/dds/pose_inbox.hpp"
#include "nav/dds/sample_checks.hpp"

namespace nav::dds {
namespace {

using namespace testing;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

TEST(DdsSampleChecks, ValidSamplesPass) {
  EXPECT_EQ(check_sample(make_pose(1, 10)), SampleFault::none);
  EXPECT_EQ(check_sample(*make_frame(640, 480, 10)), SampleFault::none);
  EXPECT_EQ(check_sample(make_needle(20, 10)), SampleFault::none);
  EXPECT_EQ(check_sample(make_prediction(10)), SampleFault::none);
  EXPECT_EQ(check_sample(*make_surface(100, 10)), SampleFault::none);
  EXPECT_EQ(check_sample(make_health(10)), SampleFault::none);
  EXPECT_EQ(check_sample(make_truth(10)), SampleFault::none);
}

TEST(DdsSampleChecks, NaNOrInfinityAnywhereInAPoseIsNonFinite) {
  ToolPose pose = make_pose(1, 10);
  pose.position_m[1] = kNaN;
  EXPECT_EQ(check_sample(pose), SampleFault::non_finite);
  pose = make_pose(1, 10);
  pose.orientation_wxyz[3] = std::numeric_limits<double>::infinity();
  EXPECT_EQ(check_sample(pose), SampleFault::non_finite);
  pose = make_pose(1, 10);
  pose.position_covariance_m2[4] = kNaN;
  EXPECT_EQ(check_sample(pose), SampleFault::non_finite);
  pose = make_pose(1, 10);
  pose.quality = std::numeric_limits<float>::quiet_NaN();
  EXPECT_EQ(check_sample(pose), SampleFault::non_finite);
}

TEST(DdsSampleChecks, QuaternionMustBeUnitWithinTolerance) {
  ToolPose pose = make_pose(1, 10);
  pose.orientation_wxyz = {1.0, 0.0, 0.0, 0.0};
  EXPECT_EQ(check_sample(pose), SampleFault::none);
  pose.orientation_wxyz = {1.0 + 0.5 * kQuaternionNormTolerance, 0.0, 0.0, 0.0};
  EXPECT_EQ(check_sample(pose), SampleFault::none);
  pose.orientation_wxyz = {1.0 + 2.0 * kQuaternionNormTolerance, 0.0, 0.0, 0.0};
  EXPECT_EQ(check_sample(pose), SampleFault::non_unit_quaternion);
  pose.orientation_wxyz = {0.0, 0.0, 0.0, 0.0};
  EXPECT_EQ(check_sample(pose), SampleFault::non_unit_quaternion);
  pose.orientation_wxyz = {0.5, 0.5, 0.5, 0.6};
  EXPECT_EQ(check_sample(pose), SampleFault::non_unit_quaternion);
}

TEST(DdsSampleChecks, FrameSizesAndGeometryAreChecked) {
  auto frame = make_frame(640, 480, 10);
  frame->width_px = 0;
  EXPECT_EQ(check_sample(*frame), SampleFault::wrong_size);
  frame->width_px = 2048;
  frame->height_px = 1024;
  EXPECT_EQ(check_sample(*frame), SampleFault::wrong_size);
  frame = make_frame(640, 480, 10);
  frame->pixel_spacing_m[0] = 0.0;
  EXPECT_EQ(check_sample(*frame), SampleFault::wrong_size);
  frame = make_frame(640, 480, 10);
  frame->depth_m = kNaN;
  EXPECT_EQ(check_sample(*frame), SampleFault::non_finite);
}

TEST(DdsSampleChecks, NonFiniteOutputsAreRefused) {
  NeedleState needle = make_needle(10, 1);
  needle.shape_points_m[9][2] = kNaN;
  EXPECT_EQ(check_sample(needle), SampleFault::non_finite);
  needle = make_needle(10, 1);
  needle.shape_points_m[10][2] = kNaN;  // beyond point_count: not part of the sample
  EXPECT_EQ(check_sample(needle), SampleFault::none);
  needle.point_count = kMaxNeedlePoints + 1;
  EXPECT_EQ(check_sample(needle), SampleFault::wrong_size);

  TargetPrediction prediction = make_prediction(1);
  prediction.covariance_m2[8] = kNaN;
  EXPECT_EQ(check_sample(prediction), SampleFault::non_finite);

  GroundTruth truth = make_truth(1);
  truth.needle_tip_m[1] = kNaN;
  EXPECT_EQ(check_sample(truth), SampleFault::non_finite);

  auto surface = make_surface(10, 1);
  surface->vertex_positions_m[3][0] = std::numeric_limits<float>::infinity();
  EXPECT_EQ(check_sample(*surface), SampleFault::non_finite);
}

TEST(DdsSampleChecks, StreamOrderRefusesEarlierTimesOnly) {
  StreamOrder order;
  EXPECT_EQ(order.advance(100), SampleFault::none);
  EXPECT_EQ(order.advance(100), SampleFault::none);
  EXPECT_EQ(order.advance(99), SampleFault::time_backwards);
  EXPECT_EQ(order.advance(101), SampleFault::none);
  EXPECT_EQ(order.advance(100), SampleFault::time_backwards);
}

TEST(DdsSampleChecks, PoseInboxRefusesUnknownToolsAndKeepsTimeOrderPerTool) {
  PoseInbox inbox{3, 8};
  EXPECT_EQ(inbox.tool_count(), 2u);
  EXPECT_EQ(inbox.slot_of(8), 1);
  EXPECT_EQ(inbox.slot_of(4), -1);
  EXPECT_EQ(inbox.offer(make_pose(4, 10)), SampleFault::unknown_tool);
  EXPECT_EQ(inbox.offer(make_pose(3, 200)), SampleFault::none);
  EXPECT_EQ(inbox.offer(make_pose(8, 100)), SampleFault::none);  // another tool: its own order
  EXPECT_EQ(inbox.offer(make_pose(3, 150)), SampleFault::time_backwards);
  EXPECT_EQ(inbox.accepted(), 2u);                               // the refused ones not counted
  EXPECT_EQ(inbox.offer(make_pose(3, 250)), SampleFault::none);  // replaces the one at 200 before it is taken
  EXPECT_EQ(inbox.accepted(), 3u);
  ASSERT_TRUE(inbox.update(0));
  EXPECT_EQ(inbox.latest(0).source_time_ns, 250);
  EXPECT_FALSE(inbox.update(0));
  ASSERT_TRUE(inbox.update(1));
  EXPECT_EQ(inbox.latest(1).source_time_ns, 100);
}

TEST(DdsSampleChecks, PoseBoundsRefuseLeavingTheVolumeAndMovingFasterThanAToolCan) {
  const PoseBounds bounds;  // 3 m, 2 m/s, 2 mm
  ToolPose first = make_pose(1, 0);
  first.position_m = {0.0, 0.0, 0.0};
  EXPECT_EQ(bounds.check(first, nullptr), SampleFault::none);
  ToolPose far = first;
  far.position_m = {1e300, 0.0, 0.0};
  EXPECT_EQ(bounds.check(far, nullptr), SampleFault::implausible_pose);
  far.position_m = {2.0, 2.0, 2.0};  // 3.46 m away
  EXPECT_EQ(bounds.check(far, nullptr), SampleFault::implausible_pose);
  // 16.7 ms later (60 Hz): 2 m/s allows 33 mm + 2 mm; the probe that jumped 5 cm is refused.
  ToolPose next = make_pose(1, 16'700'000);
  next.position_m = {0.034, 0.0, 0.0};
  EXPECT_EQ(bounds.check(next, &first), SampleFault::none);
  next.position_m = {0.05, 0.0, 0.0};
  EXPECT_EQ(bounds.check(next, &first), SampleFault::implausible_pose);
  // The same 5 cm after half a second: plausible. A stamp before the reference is the time
  // order's to refuse.
  next.source_time_ns = kNsPerSecond / 2;
  EXPECT_EQ(bounds.check(next, &first), SampleFault::none);
  next.source_time_ns = -1;
  EXPECT_EQ(bounds.check(next, &first), SampleFault::none);
}

TEST(DdsSampleChecks, AnImplausibleJumpNeverBecomesTheToolsReference) {
  PoseInbox inbox{1};
  ToolPose pose = make_pose(1, 0);
  pose.position_m = {0.1, 0.0, 0.0};
  EXPECT_EQ(inbox.offer(pose), SampleFault::none);
  ToolPose jump = make_pose(1, 10 * kNsPerMs);
  jump.position_m = {0.3, 0.0, 0.0};  // 20 m/s
  EXPECT_EQ(inbox.offer(jump), SampleFault::implausible_pose);
  for (TimeNs t = 20; t <= 60; t += 10) {  // the tool where it was: every pose taken
    pose.source_time_ns = t * kNsPerMs;
    EXPECT_EQ(inbox.offer(pose), SampleFault::none) << t;
  }
  ASSERT_TRUE(inbox.update(0));
  EXPECT_EQ(inbox.latest(0).position_m[0], 0.1);
}

TEST(DdsSampleChecks, CountersAddUpByReason) {
  BoundaryCounters counters;
  counters.count(SampleFault::none);
  counters.count(SampleFault::none);
  counters.count(SampleFault::malformed);
  counters.count(SampleFault::wrong_size);
  counters.count(SampleFault::non_finite);
  counters.count(SampleFault::non_unit_quaternion);
  counters.count(SampleFault::time_backwards);
  counters.count(SampleFault::time_backwards);
  counters.count(SampleFault::unknown_tool);
  counters.count(SampleFault::implausible_pose);
  counters.count(SampleFault::buffer_full);
  const BoundaryCounts counts = counters.snapshot();
  EXPECT_EQ(counts.accepted, 2u);
  EXPECT_EQ(counts.malformed, 1u);
  EXPECT_EQ(counts.wrong_size, 1u);
  EXPECT_EQ(counts.non_finite, 1u);
  EXPECT_EQ(counts.non_unit_quaternion, 1u);
  EXPECT_EQ(counts.time_backwards, 2u);
  EXPECT_EQ(counts.unknown_tool, 1u);
  EXPECT_EQ(counts.buffer_full, 1u);
  EXPECT_STREQ(sample_fault_name(SampleFault::non_unit_quaternion), "non_unit_quaternion");
  EXPECT_EQ(counts.implausible_pose, 1u);
  EXPECT_EQ(drops_by_reason(counts),
            "malformed 1, wrong_size 1, non_finite 1, non_unit_quaternion 1, time_backwards 2, unknown_tool 1, "
            "implausible_pose 1, "
            "buffer_full 1");
  EXPECT_EQ(refused_as_invalid(counts), 8u);  // all but the full buffer
  EXPECT_EQ(drops_by_reason(BoundaryCounts{.accepted = 5}), "none");
}

TEST(DdsHealthText, TheSummaryNamesTheModeTheFlagsEachInputInTroubleAndTheDrops) {
  StationHealth health;
  health.mode = StationMode::running;
  EXPECT_TRUE(station_healthy(health));
  EXPECT_EQ(health_summary(health), "station running | healthy | dropped at the boundary: none");
  health.input_flags[static_cast<std::size_t>(StationInput::probe)] =
      static_cast<std::uint32_t>(HealthFlag::stale_input);
  EXPECT_FALSE(station_healthy(health));  // an input alone is enough
  health.mode = StationMode::degraded;
  health.flags = static_cast<std::uint32_t>(HealthFlag::bad_sample);
  health.boundary.malformed = 3;
  EXPECT_EQ(health_summary(health),
            "station DEGRADED | bad_sample | probe: stale_input | dropped at the boundary: malformed 3");
  health.flags = 0;
  health.input_flags = {};
  EXPECT_FALSE(station_healthy(health));  // degraded without a flag is still not healthy
}

}  // namespace
}  // namespace nav::dds
