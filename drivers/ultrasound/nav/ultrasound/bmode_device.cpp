#include "nav/ultrasound/bmode_device.hpp"

namespace nav::ultrasound {
namespace {}  // namespace

BmodeDevice::BmodeDevice(BmodeSimulator simulator, const Eigen::Isometry3d& probe_from_image,
                         std::uint32_t probe_tool_id)
    : simulator_(std::move(simulator)),
      probe_from_image_(probe_from_image),
      probe_tool_id_(probe_tool_id),
      frame_(std::make_unique<dds::UltrasoundFrame>()) {
  const BmodeGeometry& geometry = simulator_.geometry();
  frame_->width_px = geometry.width_px;
  frame_->height_px = geometry.height_px;
  frame_->pixel_spacing_m = {geometry.spacing_m, geometry.spacing_m};
  frame_->depth_m = geometry.height_px * geometry.spacing_m;
  frame_->probe_tool_id = probe_tool_id;
}

BmodeTruth BmodeDevice::publish(dds::DdsNode& node, const Eigen::Isometry3d& liver_from_probe, TimeNs time_ns,
                                bool& published) {
  const BmodeTruth truth = simulator_.render(liver_from_probe * probe_from_image_, frame_->pixels.data());
  frame_->sequence_number = sequence_number_;
  frame_->source_time_ns = time_ns;
  dds::ToolPose pose;
  pose.tool_id = probe_tool_id_;
  pose.sequence_number = sequence_number_++;
  pose.source_time_ns = time_ns;
  pose.position_m = {liver_from_probe.translation().x(), liver_from_probe.translation().y(),
                     liver_from_probe.translation().z()};
  const Eigen::Quaterniond rotation(liver_from_probe.linear());
  pose.orientation_wxyz = {rotation.w(), rotation.x(), rotation.y(), rotation.z()};
  pose.quality = 1.0f;
  dds::set_frame_name(pose.frame_to, "liver");
  dds::set_frame_name(pose.frame_from, "probe");
  published = node.write(pose);
  published = node.write(*frame_) && published;
  return truth;
}

}  // namespace nav::ultrasound
