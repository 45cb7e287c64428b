#pragma once
// The probe pose that makes navview (run with the demo scene) draw the known scene of
// test_navview_scene.hpp where that scene gives it: its geometry is in the frame's image frame,
// and with the image frame placed on the model frame (the scene's registration and the URDF's
// probe calibration cancelled) image and model coordinates coincide.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "nav/calibration/frame_tree.hpp"
#include "nav/dds/samples.hpp"
#include "station/scene_text.hpp"

namespace nav::view::testing {

/// The demo scene's probe (tool 2) at `time_ns`, holding the image frame on the model frame:
/// tracker_from_probe = reference_from_model * inverse(probe_from_image) (no reference tool:
/// the tracker is the reference marker).
inline dds::ToolPose probe_pose_placing_image_at_model(TimeNs time_ns) {
  dds::ToolPose pose;
  auto frames =
      calibration::FrameTree::load(nav::testing::example_scene_path("../../../calibration/urdf/station.urdf"));
  EXPECT_TRUE(frames.ok());
  if (!frames.ok()) return pose;
  const auto reference_from_model = frames.value().lookup("reference_marker", "liver_model", 0);
  const auto probe_from_image = frames.value().lookup("probe_marker", "image_plane", 0);
  EXPECT_TRUE(reference_from_model.ok() && probe_from_image.ok());
  if (!reference_from_model.ok() || !probe_from_image.ok()) return pose;
  const Eigen::Isometry3d tracker_from_probe = reference_from_model.value() * probe_from_image.value().inverse();
  const Eigen::Quaterniond q(tracker_from_probe.rotation());
  pose.tool_id = 2;
  pose.source_time_ns = time_ns;
  pose.orientation_wxyz = {q.w(), q.x(), q.y(), q.z()};
  for (int i = 0; i < 3; ++i) pose.position_m[static_cast<std::size_t>(i)] = tracker_from_probe.translation()[i];
  pose.quality = 1.0f;
  return pose;
}

}  // namespace nav::view::testing
