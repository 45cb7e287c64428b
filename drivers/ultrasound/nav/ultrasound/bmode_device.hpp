#pragma once
// The synthetic B-mode simulator as a device on DDS: each tick publishes the tracked probe's
// ToolPose and the frame the probe sees (UltrasoundFrame), as a real tracked scanner would.
#include <Eigen/Geometry>
#include <cstdint>
#include <memory>

#include "nav/core/clock.hpp"
#include "nav/dds/dds_node.hpp"
#include "nav/dds/samples.hpp"
#include "nav/ultrasound/bmode_simulator.hpp"

namespace nav::ultrasound {

/// A simulated tracked probe: the simulator, the probe calibration (image frame to probe
/// frame) and the probe's tool id; the frame buffer is allocated once.
class BmodeDevice {
 public:
  BmodeDevice(BmodeSimulator simulator, const Eigen::Isometry3d& probe_from_image, std::uint32_t probe_tool_id);

  /// Renders the view of a probe at `liver_from_probe` (liver_from_probe, metres), publishes the
  /// pose (probe in "liver") and the frame, both stamped `time_ns`, on `node` (which has
  /// advertised both topics); returns the frame's truth. False in `published` if DDS refused.
  BmodeTruth publish(dds::DdsNode& node, const Eigen::Isometry3d& liver_from_probe, TimeNs time_ns, bool& published);

  const dds::UltrasoundFrame& last_frame() const noexcept { return *frame_; }

 private:
  BmodeSimulator simulator_;
  Eigen::Isometry3d probe_from_image_;
  std::uint32_t probe_tool_id_;
  std::uint64_t sequence_number_ = 0;
  std::unique_ptr<dds::UltrasoundFrame> frame_;
};

}  // namespace nav::ultrasound
