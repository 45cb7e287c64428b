// The real-time thread's hand-off of the loop's outputs to DDS (push_outputs): predictions
// (now and at the display latency) and the needle on liver-step ticks, health on its own
// period, nothing else; no allocation; a full outbox refuses and counts instead of waiting.
// The needle is its tip while the loop only tracks it, and the needle model's centreline
// with its tip force when the loop steps one; that shape reaches a display over real Fast
// DDS (loopback and shared memory) unchanged, and navview's 3-D panel draws it with an arrow
// of the tip force.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>

#include "../dds/test_navview_scene.hpp"
#include "nav/dds/station_outbox.hpp"
#include "nav/mesh/geometry.hpp"
#include "nav/station/station_channels.hpp"
#include "nav/station/station_dds.hpp"
#include "support/allocation_guard.hpp"

namespace nav::station {
namespace {

constexpr TimeNs kLatencyNs = 50 * kNsPerMs;
constexpr TimeNs kLoopToHostNs = 7 * kNsPerSecond;             // where run time 0 is on the host's clock
constexpr OutputStamps kStamps{kLoopToHostNs, kLatencyNs, 5};  // the needle tracked as tool 5
constexpr std::int64_t kHealthEvery = 100;

OperatingLoopOutputs outputs_at(std::int64_t tick, bool tissue_tick) {
  OperatingLoopOutputs o;
  o.ticks = tick;
  o.time_ns = tick * kNsPerMs;
  o.tissue_time_ns = tissue_tick ? o.time_ns : o.time_ns - kNsPerMs;
  o.tumour_now_m = {0.01, 0.02, 0.03};
  o.tumour_ahead_m = {0.011, 0.021, 0.031};
  o.needle_tip_m = {0.1, 0.2, 0.3};
  o.degraded = true;
  o.needle.flags.raise(HealthFlag::stale_input);
  return o;
}

TEST(StationOutbox, PushOutputsSendsWhatEachTickOwesWithoutAllocating) {
  auto outbox = std::make_unique<dds::StationOutbox>();
  std::size_t allocations = 0;
  {
    testing::AllocationGuard guard;
    push_outputs(*outbox, outputs_at(1, false), kStamps, kHealthEvery, 0, 0);     // needle tick: nothing
    push_outputs(*outbox, outputs_at(10, true), kStamps, kHealthEvery, 0, 0);     // liver step
    push_outputs(*outbox, outputs_at(100, false), kStamps, kHealthEvery, 3, 42);  // health period
    allocations = guard.allocations();
  }
  EXPECT_EQ(allocations, 0u);
  dds::TargetPrediction now, ahead, extra;
  ASSERT_TRUE(outbox->predictions.try_pop(now));
  ASSERT_TRUE(outbox->predictions.try_pop(ahead));
  EXPECT_FALSE(outbox->predictions.try_pop(extra));
  EXPECT_EQ(now.horizon_ns, 0);
  EXPECT_EQ(ahead.horizon_ns, kLatencyNs);
  EXPECT_EQ(now.source_time_ns, outputs_at(10, true).tissue_time_ns + kLoopToHostNs);  // on the host's clock
  EXPECT_DOUBLE_EQ(now.position_m[2], 0.03);
  EXPECT_DOUBLE_EQ(ahead.position_m[2], 0.031);
  dds::NeedleState needle;
  ASSERT_TRUE(outbox->needle.try_pop(needle));
  EXPECT_EQ(needle.point_count, 1u);
  EXPECT_EQ(needle.tool_id, 5u);  // the scene's needle
  EXPECT_DOUBLE_EQ(needle.shape_points_m[0][1], 0.2);
  EXPECT_FALSE(outbox->needle.try_pop(needle));
  dds::StationHealth health;
  ASSERT_TRUE(outbox->health.try_pop(health));
  EXPECT_EQ(health.mode, dds::StationMode::degraded);
  HealthFlags stale;
  stale.raise(HealthFlag::stale_input);
  EXPECT_NE(health.flags & stale.bits(), 0u);
  EXPECT_EQ(health.deadline_misses, 3u);
  EXPECT_EQ(health.step_time_max_ns, 42);
  EXPECT_EQ(health.source_time_ns, outputs_at(100, false).time_ns + kLoopToHostNs);
  EXPECT_FALSE(outbox->health.try_pop(health));
}

/// `o` with a needle model's state: 21 nodes bent along y = 0.02 m ((x + 0.06) / 0.12)^2 from
/// the base at x = -0.06 m to the tip at x = 0.06 m (z = 0), and a tip force of 0.5 N along -y.
OperatingLoopOutputs with_bent_needle(OperatingLoopOutputs o) {
  NeedleShapeOutputs& shape = o.needle_shape;
  shape.node_count = 21;
  for (int i = 0; i < shape.node_count; ++i) {
    const double s = i / 20.0;
    shape.centreline_m[static_cast<std::size_t>(i)] = {-0.06 + 0.12 * s, 0.02 * s * s, 0.0};
  }
  shape.tip_force_n = {0.0, -0.5, 0.0};
  shape.base_force_n = {0.1, 0.2, 0.3};
  return o;
}

TEST(StationOutbox, WithANeedleModelTheNeedleStateIsItsCentrelineAndTipForce) {
  auto outbox = std::make_unique<dds::StationOutbox>();
  const OperatingLoopOutputs o = with_bent_needle(outputs_at(10, true));
  std::size_t allocations = 0;
  {
    testing::AllocationGuard guard;
    push_outputs(*outbox, o, kStamps, kHealthEvery, 0, 0);
    allocations = guard.allocations();
  }
  EXPECT_EQ(allocations, 0u);
  auto needle = std::make_unique<dds::NeedleState>();
  ASSERT_TRUE(outbox->needle.try_pop(*needle));
  ASSERT_EQ(needle->point_count, 21u);
  for (std::size_t i = 0; i < 21; ++i)
    for (std::size_t c = 0; c < 3; ++c) EXPECT_EQ(needle->shape_points_m[i][c], o.needle_shape.centreline_m[i][c]) << i;
  EXPECT_EQ(needle->tip_force_n[1], -0.5);
  EXPECT_EQ(needle->shape_points_m[21][0], 0.0);  // nothing beyond the model's nodes
}

TEST(StationOutbox, TheNeedlesShapeReachesADisplayOverDdsWhichDrawsItWithItsTipForce) {
  auto outbox = std::make_unique<dds::StationOutbox>();
  const OperatingLoopOutputs o = with_bent_needle(outputs_at(10, true));
  push_outputs(*outbox, o, kStamps, kHealthEvery, 0, 0);
  auto station = make_station_node(156, "nav_test_station").value();
  auto display = make_station_node(156, "nav_test_display").value();
  auto received = std::make_unique<dds::RingSink<dds::NeedleState, 4>>();
  ASSERT_TRUE(station->advertise<dds::NeedleState>().ok());
  ASSERT_TRUE(display->subscribe(*received).ok());
  ASSERT_TRUE(station->wait_for_match(dds::Topic::needle_state, 1, 10 * kNsPerSecond));
  dds::OutboxPublisher publisher;
  EXPECT_EQ(publisher.publish(*outbox, *station, 0), 1u);  // the needle (the predictions have no writer here)
  auto needle = std::make_unique<dds::NeedleState>();
  MonotonicClock clock;
  const TimeNs deadline_ns = clock.now_ns() + 5 * kNsPerSecond;
  bool arrived = false;
  while (!(arrived = received->try_pop(*needle)) && clock.now_ns() < deadline_ns)
    clock.sleep_until_ns(clock.now_ns() + kNsPerMs);
  ASSERT_TRUE(arrived) << "no needle state within 5 s";
  ASSERT_EQ(needle->point_count, 21u);
  for (std::size_t i = 0; i < 21; ++i)
    for (std::size_t c = 0; c < 3; ++c) EXPECT_EQ(needle->shape_points_m[i][c], o.needle_shape.centreline_m[i][c]) << i;
  EXPECT_EQ(needle->tip_force_n[1], -0.5);

  // navview's 3-D panel, head-on (x right, y up) on the test square, at 636.4 px per metre:
  // the needle's chords and, below its tip, the 0.5 N force arrow of 30 px.
  const auto surface = view::testing::scene_surface();
  view::Composer composer(view::testing::scene_options(), view::testing::scene_triangles());
  const cv::Mat& image = composer.render({nullptr, needle.get(), nullptr, surface.get()});
  const double panel_x = view::testing::kPanelHeightPx, centre = 99.5,
               px_per_m = view::testing::expected::kSurfacePxPerM;
  const auto pixel = [&](const Point3& p_m, double down_px) {
    return image.at<cv::Vec3b>(static_cast<int>(std::lround(centre - px_per_m * p_m[1] + down_px)),
                               static_cast<int>(std::lround(panel_x + centre + px_per_m * p_m[0])));
  };
  const auto& nodes = o.needle_shape.centreline_m;
  for (std::size_t i = 1; i < 21; ++i) {
    const Point3 chord_middle = 0.5 * (nodes[i - 1] + nodes[i]);
    EXPECT_TRUE(view::testing::near_colour(pixel(chord_middle, 0.0), view::palette::kNeedle)) << "segment " << i;
  }
  EXPECT_TRUE(view::testing::near_colour(pixel(nodes[20], 15.0), view::palette::kForce))
      << "the arrow's shaft below the tip";
  EXPECT_TRUE(view::testing::near_colour(pixel(nodes[20], 25.0), view::palette::kForce)) << "near its head";
  EXPECT_TRUE(view::testing::near_colour(pixel(nodes[20], -15.0), view::palette::kSurface, 2))
      << "nothing above the tip";
  EXPECT_TRUE(view::testing::near_colour(pixel(nodes[20], 40.0), view::palette::kSurface, 2))
      << "nothing beyond the arrow";
  // Without a needle model the station sends the tip alone (no force): a dot, no arrow.
  needle->point_count = 1;
  needle->shape_points_m[0] = nodes[20];
  needle->tip_force_n = {0.0, 0.0, 0.0};
  ASSERT_EQ(composer.render({nullptr, needle.get(), nullptr, surface.get()}).data,
            image.data);  // the same canvas, redrawn
  EXPECT_TRUE(view::testing::near_colour(pixel(nodes[20], 0.0), view::palette::kNeedle)) << "the tip";
  EXPECT_TRUE(view::testing::near_colour(pixel(nodes[20], 15.0), view::palette::kSurface, 2)) << "no arrow";
}

TEST(StationOutbox, AFullOutboxRefusesAndCounts) {
  auto outbox = std::make_unique<dds::StationOutbox>();
  for (std::int64_t tick = 0; tick < 100; tick += 10)
    push_outputs(*outbox, outputs_at(tick, true), kStamps, kHealthEvery, 0, 0);
  EXPECT_GT(outbox->dropped(), 0u);  // nobody drained it: the rings refused, the loop went on
}

}  // namespace
}  // namespace nav::station
