#pragma once
// Lock-free single-producer single-consumer ring with preallocated slots: the hand-off
// between the I/O thread and the real-time thread for streams where every item counts
// (commands, samples to assimilate, outputs to publish). Neither side ever blocks.
#include <array>
#include <atomic>
#include <cstddef>
#include <cstdint>

namespace nav {

/// Cache line size used to keep producer and consumer indices apart.
inline constexpr std::size_t kCacheLineBytes = 64;

/// A bounded FIFO of `Capacity` (a power of two) slots. Exactly one thread may push and
/// exactly one may pop. When full, try_push refuses and counts the loss; nothing blocks,
/// nothing allocates after construction.
template <typename T, std::size_t Capacity>
class SpscRing {
  static_assert(Capacity >= 2 && (Capacity & (Capacity - 1)) == 0, "Capacity must be a power of two");

 public:
  /// Producer: copies `item` in. False (and one more dropped()) when the ring is full.
  bool try_push(const T& item) noexcept {
    const std::uint64_t head = head_.load(std::memory_order_relaxed);
    if (head - tail_cache_ == Capacity) {
      tail_cache_ = tail_.load(std::memory_order_acquire);
      if (head - tail_cache_ == Capacity) {
        dropped_.fetch_add(1, std::memory_order_relaxed);
        return false;
      }
    }
    slots_[head & kMask] = item;
    head_.store(head + 1, std::memory_order_release);
    return true;
  }

  /// Consumer: moves the oldest item into `out`. False when the ring is empty.
  bool try_pop(T& out) noexcept {
    const std::uint64_t tail = tail_.load(std::memory_order_relaxed);
    if (tail == head_cache_) {
      head_cache_ = head_.load(std::memory_order_acquire);
      if (tail == head_cache_) return false;
    }
    out = slots_[tail & kMask];
    tail_.store(tail + 1, std::memory_order_release);
    return true;
  }

  /// Items waiting, as seen at the call (exact when both sides are quiet).
  std::size_t size() const noexcept {
    return static_cast<std::size_t>(head_.load(std::memory_order_acquire) - tail_.load(std::memory_order_acquire));
  }
  static constexpr std::size_t capacity() noexcept { return Capacity; }
  /// Pushes refused because the ring was full, since construction.
  std::uint64_t dropped() const noexcept { return dropped_.load(std::memory_order_relaxed); }

 private:
  static constexpr std::uint64_t kMask = Capacity - 1;

  alignas(kCacheLineBytes) std::atomic<std::uint64_t> head_{0};  // written by the producer
  std::uint64_t tail_cache_ = 0;                                 // producer's view of tail_
  std::atomic<std::uint64_t> dropped_{0};
  alignas(kCacheLineBytes) std::atomic<std::uint64_t> tail_{0};  // written by the consumer
  std::uint64_t head_cache_ = 0;                                 // consumer's view of head_
  alignas(kCacheLineBytes) std::array<T, Capacity> slots_{};
};

}  // namespace nav
