#pragma once
// The probe pose that makes navview (run with the demo scene) draw the known scene of
// test_navview_scene.hpp where that scene gives it: its geometry is in the frame's image frame,
// and with the image frame placed on the model frame (the scene's registration and the URDF's
// probe calibration cancelled) image and model coordinates coincide; and the stream of that
// scene a station would publish.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include <memory>

#include "nav/calibration/frame_tree.hpp"
#include "nav/dds/dds_node.hpp"
#include "nav/dds/samples.hpp"
#include "station/scene_text.hpp"
#include "test_navview_scene.hpp"

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

/// The known scene published as a station would, to a navview run with the demo scene.
struct SceneStream {
  std::unique_ptr<dds::UltrasoundFrame> frame = scene_frame();
  dds::NeedleState needle = scene_needle();
  dds::TargetPrediction prediction = scene_prediction();
  std::unique_ptr<dds::DeformedSurface> surface = scene_surface();

  /// Advertises every topic of the scene on `node` and waits for navview to match them.
  static ::testing::AssertionResult advertise(dds::DdsNode& node, TimeNs match_timeout_ns) {
    const bool advertised = node.advertise<dds::ToolPose>().ok() && node.advertise<dds::UltrasoundFrame>().ok() &&
                            node.advertise<dds::NeedleState>().ok() && node.advertise<dds::TargetPrediction>().ok() &&
                            node.advertise<dds::DeformedSurface>().ok();
    if (!advertised) return ::testing::AssertionFailure() << "could not advertise the scene's topics";
    for (const dds::Topic topic : {dds::Topic::tool_pose, dds::Topic::ultrasound_frame, dds::Topic::needle_state,
                                   dds::Topic::target_prediction, dds::Topic::deformed_surface}) {
      if (!node.wait_for_match(topic, 1, match_timeout_ns))
        return ::testing::AssertionFailure() << "navview did not match " << dds::topic_name(topic);
    }
    return ::testing::AssertionSuccess();
  }

  /// Moves every sample 20 ms on and writes the probe pose placing the frame, the frame (the next
  /// in sequence), the needle, the target and the surface.
  void publish(dds::DdsNode& node) {
    const TimeNs time_ns = frame->source_time_ns + 20 * kNsPerMs;
    frame->source_time_ns = needle.source_time_ns = prediction.source_time_ns = surface->source_time_ns = time_ns;
    ++frame->sequence_number;
    node.write(probe_pose_placing_image_at_model(time_ns));
    node.write(*frame);
    node.write(needle);
    node.write(prediction);
    node.write(*surface);
  }
};

}  // namespace nav::view::testing
