#include "nav/bridge/igtl_inbound.hpp"

#include <span>
#include <utility>

#include "nav/igtl/wall_clock.hpp"

namespace nav::bridge {

InboundNames inbound_names(const station::Scene& scene) {
  InboundNames names;
  names.probe_tool_id = scene.devices.tracker.tools.probe;
  if (!scene.openigtlink) return names;
  for (const auto& [device, role] : scene.openigtlink->transforms)
    if (const auto id = station::tool_id_of_role(scene.devices.tracker.tools, role)) names.tools[device] = *id;
  names.image = scene.openigtlink->image;
  return names;
}

Result<Inbound> InboundConverter::convert(const igtl::Message& message, TimeNs wall_now_ns, TimeNs device_now_ns,
                                          dds::ToolPose& pose, dds::UltrasoundFrame& frame) {
  const igtl::MessageHeader& header = message.header;
  const TimeNs stamp_ns = igtl::device_stamp_ns(header.timestamp_ns, wall_now_ns, device_now_ns);
  if (header.type == "TRANSFORM") {
    const auto tool = names_.tools.find(header.device);
    if (tool == names_.tools.end()) return Inbound::skipped;
    auto converted = igtl::tool_pose_from_transform(header, message.body, tool->second);
    if (!converted) return converted.error();
    pose = converted.value();
    pose.source_time_ns = stamp_ns;
    pose.sequence_number = ++poses_;
    return Inbound::pose;
  }
  if (header.type == "IMAGE" && (names_.image.empty() || names_.image == header.device)) {
    if (const Status converted = igtl::ultrasound_frame_from_image(header, message.body, names_.probe_tool_id, frame);
        !converted)
      return converted.error();
    frame.source_time_ns = stamp_ns;
    frame.sequence_number = ++frames_;
    return Inbound::frame;
  }
  return Inbound::skipped;
}

}  // namespace nav::bridge
