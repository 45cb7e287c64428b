#pragma once
// The real-time thread's setup: pin the calling thread to one core, lock the process's memory
// and ask for SCHED_FIFO. Each step says what happened; a step the system does not permit
// (containers, users without CAP_SYS_NICE or CAP_IPC_LOCK, a missing core) is reported
// plainly and the station runs anyway. Init-time code.
#include <string>
#include <vector>

namespace nav::station {

/// How one setup step ended.
enum class SetupOutcome {
  applied,        ///< done
  not_permitted,  ///< refused for lack of privilege (EPERM / a resource limit)
  unavailable,    ///< the request cannot be met here (no such core, bad priority)
};

/// One setup step and what became of it.
struct SetupStep {
  std::string name;  ///< "pin to core", "lock memory", "SCHED_FIFO"
  SetupOutcome outcome = SetupOutcome::unavailable;
  std::string detail;  ///< one sentence: what happened and what the station does about it
};

/// Pins the calling thread to `core` (pthread_setaffinity_np).
SetupStep pin_to_core(int core);

/// Locks the process's current and future pages in memory (mlockall MCL_CURRENT|MCL_FUTURE).
SetupStep lock_memory();

/// Asks SCHED_FIFO at `priority` (1..99) for the calling thread.
SetupStep request_fifo(int priority);

/// What the real-time thread asks for.
struct RealtimePlan {
  int core = 1;
  int priority = 80;
  bool lock_memory = true;
};

/// Applies `plan` to the calling thread: pin, lock (if asked), SCHED_FIFO, in that order.
std::vector<SetupStep> apply_realtime_setup(const RealtimePlan& plan);

/// What apply_realtime_setup would do here: runs it on a short-lived thread, then unlocks
/// the memory again, so that the calling process is left as it was.
std::vector<SetupStep> probe_realtime_setup(const RealtimePlan& plan);

/// "applied", "not permitted" or "unavailable".
const char* outcome_name(SetupOutcome outcome);

}  // namespace nav::station
