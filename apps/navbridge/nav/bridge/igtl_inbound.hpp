#pragma once
// What comes in from a PlusServer, as the station's device samples: a TRANSFORM whose device
// name the scene maps to a tool becomes that tool's pose, and so does each TDATA element whose
// name the scene maps; the scene's IMAGE device (any IMAGE when it names none) becomes an
// ultrasound frame of the probe; all restamped from wall-clock time to the devices' clock.
// Other types and names are skipped; a message (or a TDATA element) that is not what it says
// is refused with an Error naming its device and field, and the rest of the message goes on.
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "nav/core/error.hpp"
#include "nav/dds/samples.hpp"
#include "nav/igtl/igtl_stream.hpp"
#include "nav/station/scene.hpp"

namespace nav::bridge {

/// The scene's names for what comes in: TRANSFORM device (or TDATA element) -> tool id, the IMAGE device.
struct InboundNames {
  std::map<std::string, std::uint32_t> tools;
  std::string image;  ///< empty: any IMAGE
  std::uint32_t probe_tool_id = 0;
};

/// The names of `scene`'s openigtlink section, its roles as the scene's tool ids.
InboundNames inbound_names(const station::Scene& scene);

/// What one message became.
struct Converted {
  std::vector<dds::ToolPose> poses;  ///< a TRANSFORM's pose, or a TDATA's mapped elements'
  bool frame = false;                ///< an IMAGE became the frame
  std::uint64_t skipped = 0;         ///< the message, or TDATA elements, the scene does not map
  std::vector<Error> refused;        ///< the message, or TDATA elements, refused
};

/// Turns messages into samples; keeps the sequence numbers of what it made.
class InboundConverter {
 public:
  explicit InboundConverter(InboundNames names) : names_(std::move(names)) {}

  /// `message` as poses or a frame (into `frame`), stamped on the devices' clock from the nows
  /// given, into `out` (cleared first).
  void convert(const igtl::Message& message, TimeNs wall_now_ns, TimeNs device_now_ns, Converted& out,
               dds::UltrasoundFrame& frame);

 private:
  /// A pose converted (or refused) into `out`, restamped and numbered.
  void take_pose(Result<dds::ToolPose> pose, TimeNs stamp_ns, Converted& out);

  InboundNames names_;
  std::uint64_t poses_ = 0;
  std::uint64_t frames_ = 0;
};

}  // namespace nav::bridge
