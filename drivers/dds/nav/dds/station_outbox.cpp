#include "nav/dds/station_outbox.hpp"

#include "nav/core/health.hpp"

namespace nav::dds {
namespace {

/// Pops every item of `ring` into `item` and writes it; returns how many DDS accepted.
template <typename Ring, typename Sample, typename Prepare>
std::size_t drain(Ring& ring, Sample& item, DdsNode& node, Prepare prepare) {
  std::size_t written = 0;
  while (ring.try_pop(item)) {
    prepare(item);
    if (node.write(item)) ++written;
  }
  return written;
}

}  // namespace

OutboxPublisher::OutboxPublisher(TimeNs bad_sample_hold_ns)
    : surface_(std::make_unique<DeformedSurface>()), bad_sample_hold_ns_(bad_sample_hold_ns) {}

std::size_t OutboxPublisher::publish(StationOutbox& outbox, DdsNode& node, TimeNs now_ns) {
  const auto as_is = [](const auto&) {};
  NeedleState needle;
  TargetPrediction prediction;
  StationHealth health;
  std::size_t written = drain(outbox.needle, needle, node, as_is);
  written += drain(outbox.predictions, prediction, node, as_is);
  written += drain(outbox.surfaces, *surface_, node, as_is);
  written += drain(outbox.health, health, node, [&](StationHealth& sample) {
    sample.boundary = node.boundary_counts();
    if (outbox.dropped() > 0) sample.flags |= static_cast<std::uint32_t>(HealthFlag::buffer_overrun);
    const std::uint64_t refused = refused_as_invalid(sample.boundary);
    if (refused > refused_seen_) {
      refused_seen_ = refused;
      last_refusal_seen_ns_ = now_ns;
      refused_any_ = true;
    }
    if (refused_any_ && now_ns - last_refusal_seen_ns_ < bad_sample_hold_ns_) sample.flags |= static_cast<std::uint32_t>(HealthFlag::bad_sample);
  });
  return written;
}

}  // namespace nav::dds
