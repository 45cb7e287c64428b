#pragma once
// Fast DDS's shared-memory transport keeps each participant's segment as a file in /dev/shm
// (fastrtps_<16 hex digits>) beside a lock file (the same name and "_el") that its process
// holds locked while it lives. A participant that dies without closing (SIGKILL, a crash)
// leaves both behind, megabytes each, until the host restarts. Every DdsNode with shared
// memory removes such leftovers before it joins (the ports, fastrtps_port<N>, are reused by
// name and Fast DDS repairs them itself).
#include <chrono>
#include <cstddef>
#include <string>

namespace nav::dds {

/// What one cleanup saw: segments removed (their process gone) and segments in use.
struct SharedMemoryCleanup {
  std::size_t removed = 0;
  std::size_t in_use = 0;
};

/// Removes the segments in `folder` whose lock file no process holds and is older than
/// `min_age` (a segment being created has its lock file for a moment before it locks it).
/// Never throws; a file it cannot open or remove is left as it is.
SharedMemoryCleanup remove_dead_shared_memory(const std::string& folder = "/dev/shm",
                                              std::chrono::seconds min_age = std::chrono::seconds(1)) noexcept;

}  // namespace nav::dds
