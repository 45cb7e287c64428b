#pragma once
// Lock-free latest-value hand-off between one writer and one reader: the writer always
// has a free slot to fill, the reader always gets the most recent complete value, and
// neither waits. For state-like streams where only the newest value matters (tool poses,
// the latest prediction).
#include <array>
#include <atomic>
#include <cstdint>

namespace nav {

/// Three preallocated slots of T: one being written, one being read, one in between.
/// Exactly one writer thread and one reader thread.
template <typename T>
class TripleBuffer {
 public:
  /// Writer: the slot to fill before publish(). It holds stale data; overwrite it whole.
  T& write_slot() noexcept { return slots_[write_index_]; }

  /// Writer: makes the filled slot the latest value.
  void publish() noexcept {
    const std::uint8_t previous = middle_.exchange(write_index_ | kFreshBit, std::memory_order_acq_rel);
    write_index_ = previous & kIndexMask;
  }

  /// Writer: copies `value` in and publishes it.
  void write(const T& value) noexcept {
    write_slot() = value;
    publish();
  }

  /// Reader: takes the latest published value if there is one newer than the last taken.
  /// Returns true when read() changed.
  bool update() noexcept {
    if ((middle_.load(std::memory_order_relaxed) & kFreshBit) == 0) return false;
    const std::uint8_t previous = middle_.exchange(read_index_, std::memory_order_acq_rel);
    read_index_ = previous & kIndexMask;
    return true;
  }

  /// Reader: the value taken by the last successful update() (value-initialised before).
  const T& read() const noexcept { return slots_[read_index_]; }

 private:
  static constexpr std::uint8_t kIndexMask = 0x3;
  static constexpr std::uint8_t kFreshBit = 0x4;

  std::array<T, 3> slots_{};
  alignas(64) std::atomic<std::uint8_t> middle_{1};
  alignas(64) std::uint8_t write_index_ = 0;
  alignas(64) std::uint8_t read_index_ = 2;
};

}  // namespace nav
