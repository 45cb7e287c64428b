#include "nav/station/image_placement.hpp"

#include <utility>

#include "nav/station/tumour_observer.hpp"

namespace nav::station {
namespace {

constexpr TimeNs kLargestPoseGapNs = 100 * kNsPerMs;

}  // namespace

Result<ImagePlacement> ImagePlacement::create(const Scene& scene) {
  auto reference_from_model = scene_reference_from_model(scene);
  if (!reference_from_model) return reference_from_model.error();
  auto imaging = scene_probe_imaging(scene);
  if (!imaging) return imaging.error();
  PoseTrackOptions options;
  options.max_age_ns = kLargestPoseGapNs;  // PLUS sends 20 to 60 poses a second: no restart between two
  options.max_extrapolation_ns = kLargestPoseGapNs;
  auto probe = PoseTrack::create(options);
  if (!probe) return probe.error();
  const Eigen::Isometry3d& calibration = imaging.value().probe_from_image;
  return ImagePlacement(scene.devices.tracker.tools.probe,
                        TrackerRegistration(reference_from_model.value(), scene.devices.tracker.tools.reference),
                        std::move(probe).value(),
                        RigidPose{calibration.translation(), Eigen::Quaterniond(calibration.rotation()).normalized()});
}

ImagePlacement::ImagePlacement(std::uint32_t probe_tool, TrackerRegistration registration, PoseTrack probe,
                               const RigidPose& probe_from_image)
    : probe_tool_(probe_tool),
      registration_(std::move(registration)),
      probe_(std::move(probe)),
      probe_from_image_(probe_from_image) {}

void ImagePlacement::add_pose(const dds::ToolPose& pose) {
  if (registration_.take_reference(pose) || pose.tool_id != probe_tool_) return;
  const auto& q = pose.orientation_wxyz;
  probe_.push({pose.source_time_ns, RigidPose{{pose.position_m[0], pose.position_m[1], pose.position_m[2]},
                                              Eigen::Quaterniond(q[0], q[1], q[2], q[3]).normalized()}});
}

std::optional<RigidPose> ImagePlacement::model_from_image(TimeNs capture_ns) const {
  const std::optional<RigidPose> model_from_tracker = registration_.model_from_tracker();
  if (!model_from_tracker || probe_.size() == 0) return std::nullopt;
  const PoseQuery probe = probe_.sample_at(capture_ns);
  if (probe.flags.has(HealthFlag::missing_input) || probe.age_ns > kLargestPoseGapNs) return std::nullopt;
  return compose(compose(*model_from_tracker, probe.pose), probe_from_image_);
}

}  // namespace nav::station
