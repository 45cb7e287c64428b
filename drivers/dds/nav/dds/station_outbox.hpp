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

/// Drains a StationOutbox into a DdsNode (I/O thread). Health samples leave with the node's
/// boundary counts filled in and HealthFlag::buffer_overrun raised if the outbox dropped.
class OutboxPublisher {
 public:
  OutboxPublisher();
  /// Publishes everything waiting in `outbox`; returns the number of samples written.
  std::size_t publish(StationOutbox& outbox, DdsNode& node);

 private:
  std::unique_ptr<DeformedSurface> surface_;  // the largest output, popped into here
};

}  // namespace nav::dds
