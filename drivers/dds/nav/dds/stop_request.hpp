#pragma once
// A process-wide stop request raised by SIGINT or SIGTERM, so that the long-running DDS
// tools (navtool record, navview) leave their loops and delete their participants: a clean
// shutdown releases Fast DDS's shared-memory segments and, for a recorder, writes the index.
#include <atomic>
#include <csignal>

namespace nav::dds {

/// Whether SIGINT or SIGTERM arrived since install_stop_handlers().
inline std::atomic<bool> g_stop_requested{false};

/// Routes SIGINT and SIGTERM to the stop request instead of ending the process.
inline void install_stop_handlers() {
  static_assert(std::atomic<bool>::is_always_lock_free, "the signal handler needs a lock-free flag");
  const auto request_stop = [](int) { g_stop_requested.store(true, std::memory_order_relaxed); };
  std::signal(SIGINT, request_stop);
  std::signal(SIGTERM, request_stop);
}

/// True once a stop was requested.
inline bool stop_requested() noexcept { return g_stop_requested.load(std::memory_order_relaxed); }

}  // namespace nav::dds
