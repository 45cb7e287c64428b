#pragma once
// Where the station's ultrasound frames lie in the model frame, for displays: the probe's
// tracked pose at a frame's capture time (SLERP between its samples, fusion's PoseTrack), taken
// into the model frame by the scene's registration (its reference tool's newest pose, or the
// tracker fixed to the patient), times the probe calibration probe_from_image of the scene's
// URDF, the station's own chain (tumour_observer.hpp). For displays (the OpenIGTLink bridge)
// and session exports.
#include <cstdint>
#include <optional>

#include "nav/core/error.hpp"
#include "nav/dds/samples.hpp"
#include "nav/fusion/pose_track.hpp"
#include "nav/fusion/rigid_pose.hpp"
#include "nav/station/scene.hpp"
#include "nav/station/tracker_registration.hpp"

namespace nav::station {

/// Places frames of one scene's probe. One thread.
class ImagePlacement {
 public:
  /// The placement of `scene`'s probe; an Error names the scene's frames.urdf when a chain is missing.
  static Result<ImagePlacement> create(const Scene& scene);

  /// Takes a pose of the probe or of the reference tool; other tools' are ignored.
  void add_pose(const dds::ToolPose& pose);

  /// model_from_image at `capture_ns` (the devices' clock), the image frame's origin at its
  /// first pixel; nothing before a registration, or without a probe pose within 100 ms.
  std::optional<RigidPose> model_from_image(TimeNs capture_ns) const;

 private:
  ImagePlacement(std::uint32_t probe_tool, TrackerRegistration registration, PoseTrack probe,
                 const RigidPose& probe_from_image);

  std::uint32_t probe_tool_;
  TrackerRegistration registration_;
  PoseTrack probe_;  ///< tracker_from_probe
  RigidPose probe_from_image_;
};

}  // namespace nav::station
