#include "nav/station/realtime_thread.hpp"

#include <pthread.h>
#include <sched.h>
#include <sys/mman.h>
#include <sys/resource.h>

#include <cerrno>
#include <cstring>
#include <thread>

namespace nav::station {

namespace {

std::string errno_text(int error) {
  return std::string(std::strerror(error)) + " (errno " + std::to_string(error) + ")";
}

/// The cores this process may run on, space-separated ("0 1").
std::string allowed_cores() {
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof set, &set) != 0) return "unknown";
  std::string cores;
  for (int core = 0; core < CPU_SETSIZE; ++core)
    if (CPU_ISSET(core, &set)) cores += (cores.empty() ? "" : " ") + std::to_string(core);
  return cores;
}

/// The soft limit of `resource` as text ("unlimited" or the number, with `unit`).
std::string limit_text(int resource, const char* unit) {
  rlimit limit{};
  if (getrlimit(resource, &limit) != 0) return "unknown";
  return limit.rlim_cur == RLIM_INFINITY ? "unlimited" : std::to_string(limit.rlim_cur) + unit;
}

}  // namespace

const char* outcome_name(SetupOutcome outcome) {
  switch (outcome) {
    case SetupOutcome::applied:
      return "applied";
    case SetupOutcome::not_permitted:
      return "not permitted";
    case SetupOutcome::unavailable:
      return "unavailable";
  }
  return "unavailable";
}

SetupStep pin_to_core(int core) {
  SetupStep step{"pin to core", SetupOutcome::unavailable, ""};
  if (core < 0 || core >= CPU_SETSIZE) {
    step.detail = "core " + std::to_string(core) + " does not exist; the thread runs unpinned";
    return step;
  }
  cpu_set_t set;
  CPU_ZERO(&set);
  CPU_SET(core, &set);
  const int error = pthread_setaffinity_np(pthread_self(), sizeof set, &set);
  if (error == 0) {
    step.outcome = SetupOutcome::applied;
    step.detail = "pinned to core " + std::to_string(core);
  } else {
    step.outcome = error == EPERM ? SetupOutcome::not_permitted : SetupOutcome::unavailable;
    step.detail = "cannot pin to core " + std::to_string(core) + ": " + errno_text(error) +
                  "; this process may use cores " + allowed_cores() + "; the thread runs unpinned";
  }
  return step;
}

SetupStep lock_memory() {
  SetupStep step{"lock memory", SetupOutcome::applied, "current and future pages locked (no page faults to disk)"};
  if (mlockall(MCL_CURRENT | MCL_FUTURE) == 0) return step;
  const int error = errno;
  step.outcome = error == EPERM || error == ENOMEM ? SetupOutcome::not_permitted : SetupOutcome::unavailable;
  step.detail = "mlockall refused: " + errno_text(error) + " (RLIMIT_MEMLOCK " + limit_text(RLIMIT_MEMLOCK, " bytes") +
                ", CAP_IPC_LOCK needed beyond it); memory stays pageable";
  return step;
}

SetupStep request_fifo(int priority) {
  SetupStep step{"SCHED_FIFO", SetupOutcome::unavailable, ""};
  const int low = sched_get_priority_min(SCHED_FIFO);
  const int high = sched_get_priority_max(SCHED_FIFO);
  if (priority < low || priority > high) {
    step.detail = "priority " + std::to_string(priority) + " is outside [" + std::to_string(low) + ", " +
                  std::to_string(high) + "]; the thread keeps the normal scheduler";
    return step;
  }
  sched_param parameters{};
  parameters.sched_priority = priority;
  const int error = pthread_setschedparam(pthread_self(), SCHED_FIFO, &parameters);
  if (error == 0) {
    step.outcome = SetupOutcome::applied;
    step.detail = "SCHED_FIFO at priority " + std::to_string(priority);
    return step;
  }
  step.outcome = error == EPERM ? SetupOutcome::not_permitted : SetupOutcome::unavailable;
  step.detail = "SCHED_FIFO " + std::to_string(priority) + " refused: " + errno_text(error) + " (RLIMIT_RTPRIO " +
                limit_text(RLIMIT_RTPRIO, "") +
                ", CAP_SYS_NICE needed beyond it); the thread keeps the normal scheduler";
  return step;
}

std::vector<SetupStep> apply_realtime_setup(const RealtimePlan& plan) {
  std::vector<SetupStep> steps;
  steps.push_back(pin_to_core(plan.core));
  if (plan.lock_memory) steps.push_back(lock_memory());
  steps.push_back(request_fifo(plan.priority));
  return steps;
}

std::vector<SetupStep> probe_realtime_setup(const RealtimePlan& plan) {
  std::vector<SetupStep> steps;
  std::thread probe([&] { steps = apply_realtime_setup(plan); });
  probe.join();
  for (const SetupStep& step : steps)
    if (step.name == "lock memory" && step.outcome == SetupOutcome::applied) munlockall();
  return steps;
}

}  // namespace nav::station
