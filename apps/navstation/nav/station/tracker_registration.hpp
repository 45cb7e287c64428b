#pragma once
// The tracker-to-model registration. Tools are tracked in the tracker's frame; the models live
// in the liver model's frame. The URDF's fixed joint `reference_marker -> liver_model`
// (navtool calib register) places the model on the reference marker. When the scene tracks a
// reference tool (devices.tracker.tools.reference), its latest pose places that marker in the
// tracker, so that tracker and patient may move apart; without one, the reference marker is
// the tracker's origin (a tracker fixed to the patient). I/O-thread code: no allocation.
#include <cstdint>
#include <optional>

#include "nav/core/error.hpp"
#include "nav/dds/samples.hpp"
#include "nav/fusion/rigid_pose.hpp"
#include "nav/station/scene.hpp"

namespace nav::station {

/// reference_from_model: the URDF's `reference_marker -> liver_model` joint, or an error at the
/// scene's frames.urdf.
Result<RigidPose> scene_reference_from_model(const Scene& scene);

/// Takes tracked poses into the model frame.
class TrackerRegistration {
 public:
  TrackerRegistration(const RigidPose& reference_from_model, std::optional<std::uint32_t> reference_tool);

  /// When `pose` is the reference tool's, takes it as the reference marker's place (true).
  bool take_reference(const dds::ToolPose& pose) noexcept;
  /// model_from_tracker now; nothing until the first pose of a tracked reference.
  std::optional<RigidPose> model_from_tracker() const noexcept;
  /// Poses that came before the reference had been seen (and were not used).
  std::int64_t unregistered_poses = 0;

 private:
  RigidPose reference_from_model_;
  std::optional<std::uint32_t> reference_tool_;
  std::optional<RigidPose> model_from_tracker_;
};

}  // namespace nav::station
