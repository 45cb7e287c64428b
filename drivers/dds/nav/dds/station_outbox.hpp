#pragma once
// What the real-time core publishes, on its way to DDS: preallocated SPSC rings that the
// core pushes into (never blocking; a full ring refuses and counts) and that the I/O thread
// drains into a DdsNode with OutboxPublisher.
#include <cstddef>
#include <memory>

#include "nav/core/spsc_ring.hpp"
#include "nav/dds/dds_node.hpp"
#include "nav/dds/samples.hpp"

namespace nav::dds {

/// The core's outputs waiting to be published. Large: allocate it once, at init.
/// Producer: the real-time thread. Consumer: the I/O thread.
struct StationOutbox {
  SpscRing<NeedleState, 8> needle;
  SpscRing<TargetPrediction, 16> predictions;
  SpscRing<DeformedSurface, 2> surfaces;
  SpscRing<StationHealth, 4> health;
  /// One per tick (64 ms of them). Best effort, as their topic: a force the full ring refuses
  /// is counted in its own dropped(), not as an outbox overrun.
  SpscRing<NeedleForce, 64> needle_forces;

  /// Outputs other than needle forces refused because a ring was full, since construction.
  std::uint64_t dropped() const noexcept {
    return needle.dropped() + predictions.dropped() + surfaces.dropped() + health.dropped();
  }
};

/// How long a station's health keeps HealthFlag::bad_sample raised after its last refused
/// input sample, by default: long enough for a display refreshing at a few hertz to show it.
inline constexpr TimeNs kBadSampleHoldNs = 2 * kNsPerSecond;

/// Drains a StationOutbox into a DdsNode (I/O thread). Health samples leave with the node's
/// boundary counts, each input's refusals and the pose and frame writers it has matched filled in,
/// HealthFlag::buffer_overrun raised if the outbox dropped, and HealthFlag::bad_sample raised while the node refused an
/// input sample (any cause but a full hand-off buffer) within the last `bad_sample_hold_ns`: on the station's flags for
/// any refusal, and on an input's flags for that input's.
class OutboxPublisher {
 public:
  explicit OutboxPublisher(TimeNs bad_sample_hold_ns = kBadSampleHoldNs);
  /// Publishes everything waiting in `outbox` at `now_ns` (monotonic), with `input_refused`
  /// (each input's samples refused so far); returns the number of samples written other than
  /// needle forces, which forces_written() counts.
  std::size_t publish(StationOutbox& outbox, DdsNode& node, TimeNs now_ns,
                      const PerInput<std::uint64_t>& input_refused = {});
  /// Needle forces written so far.
  std::uint64_t forces_written() const { return forces_written_; }

 private:
  /// When a count of refusals last grew, to hold bad_sample up after it.
  struct RefusalHold {
    std::uint64_t seen = 0;
    TimeNs grew_ns = 0;
    bool grew_ever = false;
    /// Takes the count at `now_ns`; whether it grew within the last `hold_ns`.
    bool raised(std::uint64_t count, TimeNs now_ns, TimeNs hold_ns) noexcept;
  };

  std::unique_ptr<DeformedSurface> surface_;  // the largest output, popped into here
  TimeNs bad_sample_hold_ns_;
  RefusalHold station_;  ///< every sample the node refused as invalid
  PerInput<RefusalHold> inputs_{};
  std::uint64_t forces_written_ = 0;
};

}  // namespace nav::dds
