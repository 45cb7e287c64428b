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

bool OutboxPublisher::RefusalHold::raised(std::uint64_t count, TimeNs now_ns, TimeNs hold_ns) noexcept {
  if (count > seen) {
    seen = count;
    grew_ns = now_ns;
    grew_ever = true;
  }
  return grew_ever && now_ns - grew_ns < hold_ns;
}

std::size_t OutboxPublisher::publish(StationOutbox& outbox, DdsNode& node, TimeNs now_ns,
                                     const PerInput<std::uint64_t>& input_refused) {
  constexpr auto bad_sample = static_cast<std::uint32_t>(HealthFlag::bad_sample);
  const auto as_is = [](const auto&) {};
  NeedleState needle;
  TargetPrediction prediction;
  StationHealth health;
  NeedleForce force;
  forces_written_ += drain(outbox.needle_forces, force, node, as_is);
  std::size_t written = drain(outbox.needle, needle, node, as_is);
  written += drain(outbox.predictions, prediction, node, as_is);
  written += drain(outbox.surfaces, *surface_, node, as_is);
  written += drain(outbox.health, health, node, [&](StationHealth& sample) {
    sample.boundary = node.boundary_counts();
    if (outbox.dropped() > 0) sample.flags |= static_cast<std::uint32_t>(HealthFlag::buffer_overrun);
    if (station_.raised(refused_as_invalid(sample.boundary), now_ns, bad_sample_hold_ns_)) sample.flags |= bad_sample;
    sample.input_refused = input_refused;
    sample.pose_writers = static_cast<std::uint32_t>(node.matched(Topic::tool_pose));
    sample.frame_writers = static_cast<std::uint32_t>(node.matched(Topic::ultrasound_frame));
    for (std::size_t i = 0; i < kStationInputCount; ++i)
      if (inputs_[i].raised(input_refused[i], now_ns, bad_sample_hold_ns_)) sample.input_flags[i] |= bad_sample;
  });
  return written;
}

}  // namespace nav::dds
