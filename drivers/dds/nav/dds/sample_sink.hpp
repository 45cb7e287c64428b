#pragma once
// Where a DDS listener puts a sample it has accepted: an interface with one call that never
// blocks and never allocates, and its usual implementations: a preallocated SPSC ring
// (every sample), and a triple buffer (only the newest one, for displays).
#include <cstddef>

#include "nav/core/spsc_ring.hpp"
#include "nav/core/triple_buffer.hpp"
#include "nav/dds/sample_fault.hpp"

namespace nav::dds {

/// Receives validated samples of one type from one listener (the producer side of a hand-off).
template <typename Sample>
class SampleSink {
 public:
  virtual ~SampleSink() = default;
  /// Takes a copy of `sample`: none when stored, otherwise the reason it was not.
  virtual SampleFault offer(const Sample& sample) noexcept = 0;
  /// Told of a decoded sample its boundary refused before offering it (for the sink's own
  /// accounting, e.g. per tool); never blocks, never allocates.
  virtual void on_refused(const Sample& /*sample*/, SampleFault /*fault*/) noexcept {}
};

/// A sink that queues every sample for one consumer thread (frames for the core, outputs
/// for a display). Large samples: allocate the RingSink itself on the heap, at init.
template <typename Sample, std::size_t Capacity>
class RingSink final : public SampleSink<Sample> {
 public:
  SampleFault offer(const Sample& sample) noexcept override {
    return ring_.try_push(sample) ? SampleFault::none : SampleFault::buffer_full;
  }
  /// Consumer: the oldest queued sample, if any. Never blocks.
  bool try_pop(Sample& out) noexcept { return ring_.try_pop(out); }
  std::size_t size() const noexcept { return ring_.size(); }

 private:
  SpscRing<Sample, Capacity> ring_;
};

/// A sink that keeps only the newest sample for one consumer thread, never full (a display
/// wants the latest state, not a backlog). Large samples: allocate it on the heap.
template <typename Sample>
class LatestSink final : public SampleSink<Sample> {
 public:
  SampleFault offer(const Sample& sample) noexcept override {
    latest_.write(sample);
    return SampleFault::none;
  }
  /// Consumer: takes the newest sample offered since the last call; true when there was one.
  bool update() noexcept {
    if (!latest_.update()) return false;
    received_ = true;
    return true;
  }
  /// Consumer: the sample taken by the last successful update(), or null before the first.
  const Sample* latest() const noexcept { return received_ ? &latest_.read() : nullptr; }

 private:
  TripleBuffer<Sample> latest_;
  bool received_ = false;
};

}  // namespace nav::dds
