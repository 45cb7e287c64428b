#pragma once
// What comes in from a PlusServer, as the station's device samples: a TRANSFORM whose device
// name the scene maps to a tool becomes that tool's pose, the scene's IMAGE device (any IMAGE
// when it names none) becomes an ultrasound frame of the probe, both restamped from wall-clock
// time to the devices' clock. Other types and names are skipped; a message that is not what it
// says is refused with an Error naming its device and field.
#include <cstdint>
#include <map>
#include <string>

#include "nav/core/error.hpp"
#include "nav/dds/samples.hpp"
#include "nav/igtl/igtl_stream.hpp"
#include "nav/station/scene.hpp"

namespace nav::bridge {

/// The scene's names for what comes in: TRANSFORM device -> tool id, the IMAGE device.
struct InboundNames {
  std::map<std::string, std::uint32_t> tools;
  std::string image;  ///< empty: any IMAGE
  std::uint32_t probe_tool_id = 0;
};

/// The names of `scene`'s openigtlink section, its roles as the scene's tool ids.
InboundNames inbound_names(const station::Scene& scene);

/// What one message became.
enum class Inbound { pose, frame, skipped };

/// Turns messages into samples; keeps the sequence numbers of what it made.
class InboundConverter {
 public:
  explicit InboundConverter(InboundNames names) : names_(std::move(names)) {}

  /// `message` as a pose (into `pose`) or a frame (into `frame`), stamped on the devices' clock
  /// from the nows given; skipped when the scene does not map it; an Error when refused.
  Result<Inbound> convert(const igtl::Message& message, TimeNs wall_now_ns, TimeNs device_now_ns, dds::ToolPose& pose,
                          dds::UltrasoundFrame& frame);

 private:
  InboundNames names_;
  std::uint64_t poses_ = 0;
  std::uint64_t frames_ = 0;
};

}  // namespace nav::bridge
