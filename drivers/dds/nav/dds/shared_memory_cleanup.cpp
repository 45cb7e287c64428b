#include "nav/dds/shared_memory_cleanup.hpp"

#include <fcntl.h>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <ctime>
#include <filesystem>
#include <string_view>

namespace nav::dds {
namespace {

constexpr std::string_view kSegmentPrefix = "fastrtps_";
constexpr std::string_view kLockSuffix = "_el";
constexpr std::size_t kSegmentIdDigits = 16;

/// True for the lock file of a segment: fastrtps_, 16 lowercase hex digits, _el.
bool is_segment_lock(std::string_view name) noexcept {
  if (name.size() != kSegmentPrefix.size() + kSegmentIdDigits + kLockSuffix.size()) return false;
  if (!name.starts_with(kSegmentPrefix) || !name.ends_with(kLockSuffix)) return false;
  const std::string_view id = name.substr(kSegmentPrefix.size(), kSegmentIdDigits);
  return std::all_of(id.begin(), id.end(),
                     [](char c) { return std::isdigit(static_cast<unsigned char>(c)) || (c >= 'a' && c <= 'f'); });
}

/// True when no process holds `lock_path` locked (its owner is gone). The lock is taken and
/// released at once.
bool is_abandoned(const std::string& lock_path) noexcept {
  const int fd = open(lock_path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) return false;
  const bool abandoned = flock(fd, LOCK_EX | LOCK_NB) == 0;
  close(fd);  // releases the lock
  return abandoned;
}

}  // namespace

SharedMemoryCleanup remove_dead_shared_memory(const std::string& folder, std::chrono::seconds min_age) noexcept {
  SharedMemoryCleanup cleanup;
  std::error_code error;
  std::filesystem::directory_iterator entries(folder, error);
  if (error) return cleanup;
  const std::time_t newest_allowed = std::time(nullptr) - static_cast<std::time_t>(min_age.count());
  for (const std::filesystem::directory_entry& entry : entries) {
    const std::string name = entry.path().filename().string();
    if (!is_segment_lock(name)) continue;
    const std::string lock_path = entry.path().string();
    struct stat status {};
    if (stat(lock_path.c_str(), &status) != 0) continue;
    if (status.st_mtime > newest_allowed || !is_abandoned(lock_path)) {
      ++cleanup.in_use;
      continue;
    }
    const std::string segment_path = lock_path.substr(0, lock_path.size() - kLockSuffix.size());
    unlink(segment_path.c_str());
    if (unlink(lock_path.c_str()) == 0) ++cleanup.removed;
  }
  return cleanup;
}

}  // namespace nav::dds
