#include "nav/station/tracker_registration.hpp"

#include "nav/station/scene_frames.hpp"

namespace nav::station {

Result<RigidPose> scene_reference_from_model(const Scene& scene) {
  auto joint =
      scene_fixed_chain(scene, "reference_marker", "liver_model", "the registration navtool calib register writes");
  if (!joint.ok()) return joint.error();
  return RigidPose{joint.value().translation(), Eigen::Quaterniond(joint.value().rotation()).normalized()};
}

TrackerRegistration::TrackerRegistration(const RigidPose& reference_from_model,
                                         std::optional<std::uint32_t> reference_tool)
    : reference_from_model_(reference_from_model), reference_tool_(reference_tool) {
  if (!reference_tool_)
    model_from_tracker_ = inverse(reference_from_model_);  // the reference marker at the tracker's origin
}

bool TrackerRegistration::take_reference(const dds::ToolPose& pose) noexcept {
  if (!reference_tool_ || pose.tool_id != *reference_tool_) return false;
  const auto& q = pose.orientation_wxyz;
  const RigidPose tracker_from_reference{{pose.position_m[0], pose.position_m[1], pose.position_m[2]},
                                         Eigen::Quaterniond(q[0], q[1], q[2], q[3]).normalized()};
  model_from_tracker_ = inverse(compose(tracker_from_reference, reference_from_model_));
  return true;
}

std::optional<RigidPose> TrackerRegistration::model_from_tracker() const noexcept { return model_from_tracker_; }

}  // namespace nav::station
