// The real-time setup says what happened either way: pinning is checked against the core the
// thread then runs on, SCHED_FIFO and mlockall against the scheduler and the limits the
// system reports, impossible requests are refused with a plain sentence. Each case runs on
// its own thread so that the test process keeps its normal scheduling.
#include <gtest/gtest.h>

#include <pthread.h>
#include <sched.h>
#include <sys/mman.h>
#include <sys/resource.h>
#include <unistd.h>

#include <thread>

#include "nav/station/realtime_thread.hpp"

namespace nav::station {
namespace {

/// Runs `body` on a fresh thread and waits for it.
template <typename Body>
void on_own_thread(Body body) {
  std::thread thread(body);
  thread.join();
}

/// The highest core this process may run on.
int last_allowed_core() {
  cpu_set_t set;
  CPU_ZERO(&set);
  EXPECT_EQ(sched_getaffinity(0, sizeof set, &set), 0);
  int last = -1;
  for (int core = 0; core < CPU_SETSIZE; ++core)
    if (CPU_ISSET(core, &set)) last = core;
  return last;
}

TEST(RealtimeThread, PinningMovesTheThreadToItsCore) {
  const int core = last_allowed_core();
  ASSERT_GE(core, 0);
  on_own_thread([core] {
    const SetupStep step = pin_to_core(core);
    ASSERT_EQ(step.outcome, SetupOutcome::applied) << step.detail;
    EXPECT_EQ(sched_getcpu(), core);
    cpu_set_t set;
    CPU_ZERO(&set);
    ASSERT_EQ(pthread_getaffinity_np(pthread_self(), sizeof set, &set), 0);
    EXPECT_EQ(CPU_COUNT(&set), 1);
    EXPECT_TRUE(CPU_ISSET(core, &set));
  });
}

TEST(RealtimeThread, ImpossibleCoresAndPrioritiesAreRefusedPlainly) {
  on_own_thread([] {
    const SetupStep negative = pin_to_core(-1);
    EXPECT_EQ(negative.outcome, SetupOutcome::unavailable);
    EXPECT_NE(negative.detail.find("runs unpinned"), std::string::npos) << negative.detail;
    const SetupStep absent = pin_to_core(CPU_SETSIZE - 1);  // no machine here has 1024 cores
    EXPECT_NE(absent.outcome, SetupOutcome::applied);
    EXPECT_NE(absent.detail.find("may use cores"), std::string::npos) << absent.detail;
    const SetupStep priority = request_fifo(100);
    EXPECT_EQ(priority.outcome, SetupOutcome::unavailable);
    EXPECT_NE(priority.detail.find("outside [1, 99]"), std::string::npos) << priority.detail;
    EXPECT_EQ(sched_getscheduler(0), SCHED_OTHER);
  });
}

TEST(RealtimeThread, FifoIsAppliedOrRefusedAsTheSchedulerSays) {
  on_own_thread([] {
    const SetupStep step = request_fifo(10);
    int policy = -1;
    sched_param parameters{};
    ASSERT_EQ(pthread_getschedparam(pthread_self(), &policy, &parameters), 0);
    std::printf("SCHED_FIFO here: %s: %s\n", outcome_name(step.outcome), step.detail.c_str());
    if (step.outcome == SetupOutcome::applied) {
      EXPECT_EQ(policy, SCHED_FIFO);
      EXPECT_EQ(parameters.sched_priority, 10);
    } else {
      EXPECT_EQ(step.outcome, SetupOutcome::not_permitted);
      EXPECT_EQ(policy, SCHED_OTHER);
      EXPECT_NE(step.detail.find("normal scheduler"), std::string::npos) << step.detail;
    }
  });
}

TEST(RealtimeThread, MemoryLockIsAppliedOrRefusedWithTheLimit) {
  const SetupStep step = lock_memory();
  std::printf("mlockall here: %s: %s\n", outcome_name(step.outcome), step.detail.c_str());
  if (step.outcome == SetupOutcome::applied) {
    EXPECT_EQ(munlockall(), 0);
  } else {
    EXPECT_EQ(step.outcome, SetupOutcome::not_permitted);
    EXPECT_NE(step.detail.find("RLIMIT_MEMLOCK"), std::string::npos) << step.detail;
  }
}

TEST(RealtimeThread, ProbeLeavesTheCallerAsItWas) {
  cpu_set_t before;
  CPU_ZERO(&before);
  ASSERT_EQ(sched_getaffinity(0, sizeof before, &before), 0);
  const std::vector<SetupStep> steps = probe_realtime_setup({last_allowed_core(), 20, true});
  ASSERT_EQ(steps.size(), 3u);
  EXPECT_EQ(steps[0].name, "pin to core");
  EXPECT_EQ(steps[1].name, "lock memory");
  EXPECT_EQ(steps[2].name, "SCHED_FIFO");
  EXPECT_EQ(steps[0].outcome, SetupOutcome::applied) << steps[0].detail;
  cpu_set_t after;
  CPU_ZERO(&after);
  ASSERT_EQ(sched_getaffinity(0, sizeof after, &after), 0);
  EXPECT_TRUE(CPU_EQUAL(&before, &after));
  EXPECT_EQ(sched_getscheduler(0), SCHED_OTHER);
  EXPECT_EQ(probe_realtime_setup({0, 20, false}).size(), 2u);  // no memory lock asked
}

}  // namespace
}  // namespace nav::station
