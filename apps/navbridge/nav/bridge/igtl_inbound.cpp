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

void InboundConverter::take_pose(Result<dds::ToolPose> pose, TimeNs stamp_ns, Converted& out) {
  if (!pose) {
    out.refused.push_back(pose.error());
    return;
  }
  out.poses.push_back(pose.value());
  out.poses.back().source_time_ns = stamp_ns;
  out.poses.back().sequence_number = ++poses_;
}

void InboundConverter::convert(const igtl::Message& message, TimeNs wall_now_ns, TimeNs device_now_ns, Converted& out,
                               dds::UltrasoundFrame& frame) {
  out.poses.clear();
  out.frame = false;
  out.skipped = 0;
  out.refused.clear();
  const igtl::MessageHeader& header = message.header;
  const TimeNs stamp_ns = igtl::device_stamp_ns(header.timestamp_ns, wall_now_ns, device_now_ns);
  if (header.type == "TRANSFORM") {
    const auto tool = names_.tools.find(header.device);
    if (tool == names_.tools.end())
      ++out.skipped;
    else
      take_pose(igtl::tool_pose_from_transform(header, message.content(), tool->second), stamp_ns, out);
  } else if (header.type == "TDATA") {
    auto elements = igtl::tracking_elements(header, message.content());
    if (!elements) {
      out.refused.push_back(elements.error());
      return;
    }
    for (const igtl::TrackingElement& element : elements.value()) {
      const auto tool = names_.tools.find(element.name);
      if (tool == names_.tools.end())
        ++out.skipped;
      else
        take_pose(igtl::tool_pose_from_element(header, element, tool->second), stamp_ns, out);
    }
  } else if (header.type == "IMAGE" && (names_.image.empty() || names_.image == header.device)) {
    if (const Status converted =
            igtl::ultrasound_frame_from_image(header, message.content(), names_.probe_tool_id, frame);
        !converted) {
      out.refused.push_back(converted.error());
      return;
    }
    frame.source_time_ns = stamp_ns;
    frame.sequence_number = ++frames_;
    out.frame = true;
  } else {
    ++out.skipped;
  }
}

}  // namespace nav::bridge
