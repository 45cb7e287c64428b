// The real-time thread's hand-off of the loop's outputs to DDS (push_outputs): predictions
// (now and at the display latency) and the needle on liver-step ticks, health on its own
// period, nothing else; no allocation; a full outbox refuses and counts instead of waiting.
#include <gtest/gtest.h>

#include <memory>

#include "nav/dds/station_outbox.hpp"
#include "nav/station/station_channels.hpp"
#include "support/allocation_guard.hpp"

namespace nav::station {
namespace {

constexpr TimeNs kLatencyNs = 50 * kNsPerMs;
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
    push_outputs(*outbox, outputs_at(1, false), kLatencyNs, kHealthEvery, 0, 0);    // needle tick: nothing
    push_outputs(*outbox, outputs_at(10, true), kLatencyNs, kHealthEvery, 0, 0);    // liver step
    push_outputs(*outbox, outputs_at(100, false), kLatencyNs, kHealthEvery, 3, 42);  // health period
    allocations = guard.allocations();
  }
  EXPECT_EQ(allocations, 0u);
  dds::TargetPrediction now, ahead, extra;
  ASSERT_TRUE(outbox->predictions.try_pop(now));
  ASSERT_TRUE(outbox->predictions.try_pop(ahead));
  EXPECT_FALSE(outbox->predictions.try_pop(extra));
  EXPECT_EQ(now.horizon_ns, 0);
  EXPECT_EQ(ahead.horizon_ns, kLatencyNs);
  EXPECT_DOUBLE_EQ(now.position_m[2], 0.03);
  EXPECT_DOUBLE_EQ(ahead.position_m[2], 0.031);
  dds::NeedleState needle;
  ASSERT_TRUE(outbox->needle.try_pop(needle));
  EXPECT_EQ(needle.point_count, 1u);
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
  EXPECT_FALSE(outbox->health.try_pop(health));
}

TEST(StationOutbox, AFullOutboxRefusesAndCounts) {
  auto outbox = std::make_unique<dds::StationOutbox>();
  for (std::int64_t tick = 0; tick < 100; tick += 10) push_outputs(*outbox, outputs_at(tick, true), kLatencyNs, kHealthEvery, 0, 0);
  EXPECT_GT(outbox->dropped(), 0u);  // nobody drained it: the rings refused, the loop went on
}

}  // namespace
}  // namespace nav::station
