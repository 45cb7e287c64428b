// The hand-off between DDS and the real-time core: the core's side of every buffer
// allocates nothing, and when the I/O thread stalls for 100 ms the core keeps its rate,
// keeps receiving poses (the DDS listener does not need the I/O thread), never waits, and
// its outbox refuses and counts what it cannot hold.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <thread>

#include "dds_test_samples.hpp"
#include "nav/core/fixed_rate_timer.hpp"
#include "nav/dds/dds_node.hpp"
#include "nav/dds/pose_inbox.hpp"
#include "nav/dds/station_outbox.hpp"
#include "support/allocation_guard.hpp"

namespace nav::dds {
namespace {

using namespace testing;

TEST(DdsHandoff, BothSidesOfTheBuffersAllocateNothing) {
  PoseInbox inbox{1, 2};
  auto frames = std::make_unique<RingSink<UltrasoundFrame, 4>>();
  auto outbox = std::make_unique<StationOutbox>();
  const ToolPose pose = make_pose(2, 10);
  const auto frame = make_frame(640, 480, 10);
  auto popped = std::make_unique<UltrasoundFrame>();
  const NeedleState needle = make_needle(16, 10);
  const TargetPrediction prediction = make_prediction(10);
  const auto surface = make_surface(1000, 10);
  const StationHealth health = make_health(10);

  nav::testing::AllocationGuard guard;
  for (int i = 0; i < 100; ++i) {
    EXPECT_EQ(inbox.offer(pose), SampleFault::none);  // listener side
    frames->offer(*frame);
    if (inbox.update(1)) {  // real-time side
      EXPECT_EQ(inbox.latest(1).tool_id, 2u);
    }
    EXPECT_TRUE(frames->try_pop(*popped));
    outbox->needle.try_push(needle);
    outbox->predictions.try_push(prediction);
    outbox->surfaces.try_push(*surface);
    outbox->health.try_push(health);
  }
  EXPECT_EQ(guard.allocations(), 0u);
}

/// What the simulated real-time loop measured.
struct LoopRecord {
  std::int64_t ticks = 0;
  std::int64_t ticks_during_stall = 0;
  std::int64_t skipped_during_stall =
      0;  ///< periods passed over in the stall, up to the first tick after it (the host held the loop)
  bool ticked_after_stall = false;
  std::int64_t fresh_poses_during_stall = 0;
  TimeNs max_work_ns = 0;
};

TEST(DdsHandoff, StalledIoThreadNeverSlowsTheRealTimeLoop) {
  constexpr TimeNs kPeriodNs = kNsPerMs;
  constexpr std::int64_t kTicks = 400;
  constexpr TimeNs kStallNs = 100 * kNsPerMs;
  auto tracker = DdsNode::create(local_network(131));
  auto station = DdsNode::create(local_network(131));
  auto display = DdsNode::create(local_network(131));
  ASSERT_TRUE(tracker.ok() && station.ok() && display.ok());
  PoseInbox inbox{1};
  auto outbox = std::make_unique<StationOutbox>();
  auto predictions = std::make_unique<RingSink<TargetPrediction, 1024>>();
  ASSERT_TRUE(tracker.value()->advertise<ToolPose>().ok());
  ASSERT_TRUE(station.value()->subscribe(inbox).ok());
  ASSERT_TRUE(station.value()->advertise<TargetPrediction>().ok());
  ASSERT_TRUE(display.value()->subscribe(*predictions).ok());
  ASSERT_TRUE(station.value()->wait_for_match(Topic::tool_pose, 1, 10 * kNsPerSecond));
  ASSERT_TRUE(station.value()->wait_for_match(Topic::target_prediction, 1, 10 * kNsPerSecond));

  MonotonicClock clock;
  std::atomic<bool> stop{false};
  std::atomic<TimeNs> stall_start_ns{0};
  std::atomic<TimeNs> stall_end_ns{0};
  std::thread tracker_thread([&] {
    while (!stop.load()) {
      tracker.value()->write(make_pose(1, clock.now_ns()));
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
  });
  std::thread io_thread([&] {
    OutboxPublisher publisher;
    const TimeNs started_ns = clock.now_ns();
    while (!stop.load()) {
      publisher.publish(*outbox, *station.value(), clock.now_ns());
      if (stall_start_ns.load() == 0 && clock.now_ns() - started_ns > 100 * kNsPerMs) {
        stall_start_ns.store(clock.now_ns());
        std::this_thread::sleep_for(std::chrono::nanoseconds(kStallNs));  // the stall
        stall_end_ns.store(clock.now_ns());
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
  });

  LoopRecord record;
  FixedRateTimer timer(clock, kPeriodNs, clock.now_ns());
  for (std::int64_t i = 0; i < kTicks; ++i) {
    const Tick tick = timer.wait_next_tick();
    const bool fresh = inbox.update(0);
    TargetPrediction prediction = make_prediction(tick.woke_ns);
    prediction.position_m = inbox.latest(0).position_m;
    outbox->predictions.try_push(prediction);
    const TimeNs done_ns = clock.now_ns();
    record.max_work_ns = std::max(record.max_work_ns, done_ns - tick.woke_ns);
    ++record.ticks;
    const TimeNs start = stall_start_ns.load();
    const TimeNs end = stall_end_ns.load();
    if (start != 0 && tick.woke_ns >= start && (end == 0 || tick.woke_ns < end)) {
      ++record.ticks_during_stall;
      record.skipped_during_stall += tick.skipped;
      if (fresh) ++record.fresh_poses_during_stall;
    } else if (end != 0 && tick.woke_ns >= end && !record.ticked_after_stall) {
      record.ticked_after_stall = true;
      record.skipped_during_stall += tick.skipped;
    }
  }
  const std::uint64_t dropped_by_outbox = outbox->predictions.dropped();
  const std::int64_t deadline_misses = timer.deadline_misses();
  // After the stall the I/O thread catches up and the display hears the core again.
  const bool display_heard = wait_until([&] { return predictions->size() > 0; });
  stop.store(true);
  tracker_thread.join();
  io_thread.join();

  std::printf(
      "ticks %lld, during the 100 ms stall %lld (%lld periods skipped) with %lld fresh poses; max tick work %.1f us; "
      "deadline misses %lld; outbox dropped %llu\n",
      static_cast<long long>(record.ticks), static_cast<long long>(record.ticks_during_stall),
      static_cast<long long>(record.skipped_during_stall), static_cast<long long>(record.fresh_poses_during_stall),
      record.max_work_ns / 1e3, static_cast<long long>(deadline_misses),
      static_cast<unsigned long long>(dropped_by_outbox));
  ASSERT_NE(stall_end_ns.load(), 0) << "the I/O thread never stalled";
  EXPECT_EQ(record.ticks, kTicks);
  // Every period of the stall ticked, or skipped while the host held the whole process (a
  // virtual machine's host may): then no tick's work was long, checked below.
  EXPECT_GE(record.ticks_during_stall + record.skipped_during_stall, 90)
      << "the loop lost its rate while the I/O thread stalled";
  ASSERT_GE(record.ticks_during_stall, 10) << "the host left the loop too little of the stall to judge it";
  EXPECT_GE(4 * record.fresh_poses_during_stall, record.ticks_during_stall)
      << "poses stopped reaching the core during the stall";
  EXPECT_LT(record.max_work_ns, 20 * kNsPerMs) << "a tick waited (for the stalled I/O thread?)";
  EXPECT_GT(dropped_by_outbox, 0u) << "the outbox should have refused outputs while nobody drained it";
  EXPECT_TRUE(display_heard);
}

}  // namespace
}  // namespace nav::dds
