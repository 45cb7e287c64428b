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

  /// Outputs refused because a ring was full, since construction.
  std::uint64_t dropped() const noexcept {
    return needle.dropped() + predictions.dropped() + surfaces.dropped() + health.dropped();
  }
};

/// How long a station's health keeps HealthFlag::bad_sample raised after its last refused
/// input sample, by default: long enough for a display refreshing at a few hertz to show it.
inline constexpr TimeNs kBadSampleHoldNs = 2 * kNsPerSecond;

/// Drains a StationOutbox into a DdsNode (I/O thread). Health samples leave with the node's
/// boundary counts filled in, HealthFlag::buffer_overrun raised if the outbox dropped, and
/// HealthFlag::bad_sample raised while the node refused an input sample (any cause but a
/// full hand-off buffer) within the last `bad_sample_hold_ns`.
class OutboxPublisher {
 public:
  explicit OutboxPublisher(TimeNs bad_sample_hold_ns = kBadSampleHoldNs);
  /// Publishes everything waiting in `outbox` at `now_ns` (monotonic); returns the number of
  /// samples written.
  std::size_t publish(StationOutbox& outbox, DdsNode& node, TimeNs now_ns);

 private:
  std::unique_ptr<DeformedSurface> surface_;  // the largest output, popped into here
  TimeNs bad_sample_hold_ns_;
  std::uint64_t refused_seen_ = 0;  ///< invalid samples the node had refused at the last health sample
  TimeNs last_refusal_seen_ns_ = 0;
  bool refused_any_ = false;
};

}  // namespace nav::dds
