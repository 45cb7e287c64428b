#pragma once
// The fixed-capacity history behind fusion's tracks: a ring whose storage is allocated
// once, where a new sample overwrites the oldest when full. Single-threaded (the lock-free
// hand-off between threads is nav::SpscRing).
#include <cstddef>
#include <vector>

namespace nav {

/// The newest `capacity` samples, oldest first; push never allocates.
template <typename Sample>
class HistoryRing {
 public:
  /// Allocates storage for `capacity` (>= 1) samples. Init-time only.
  explicit HistoryRing(std::size_t capacity) : samples_(capacity) {}

  /// Appends `sample`, dropping the oldest when full.
  void push(const Sample& sample) noexcept {
    samples_[(oldest_ + count_) % samples_.size()] = sample;
    if (count_ == samples_.size())
      oldest_ = (oldest_ + 1) % samples_.size();
    else
      ++count_;
  }
  /// The sample `index` places after the oldest (index < size()).
  const Sample& at(std::size_t index) const noexcept { return samples_[(oldest_ + index) % samples_.size()]; }
  const Sample& newest() const noexcept { return at(count_ - 1); }
  void clear() noexcept { oldest_ = count_ = 0; }
  std::size_t size() const noexcept { return count_; }
  bool empty() const noexcept { return count_ == 0; }

 private:
  std::vector<Sample> samples_;
  std::size_t oldest_ = 0;
  std::size_t count_ = 0;
};

}  // namespace nav
