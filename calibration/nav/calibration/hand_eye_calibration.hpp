#pragma once
// Hand-eye calibration AX = XB: the transform X = marker_from_camera between a tracked marker
// and the camera rigidly attached to it, from simultaneous poses of the marker in the tracker
// (tracker_from_marker) and of a fixed target in the camera (camera_from_target). Rotation by the
// Park-Martin log-map fit (Kabsch on rotation vectors), then translation by least squares.
#include <vector>

#include "nav/calibration/rigid_transform.hpp"
#include "nav/core/error.hpp"

namespace nav::calibration {

/// The result of a hand-eye calibration, with the residuals of AX = XB over all motion pairs.
struct HandEyeResult {
  Transform marker_from_camera = Transform::Identity();
  double rms_rotation_residual_rad = 0.0;
  double rms_translation_residual_m = 0.0;
  std::size_t motions = 0;
};

/// Calibrates from matching pose lists. Errors: fewer than 3 poses, different counts, or
/// motions whose rotation axes are all parallel (X's rotation is then undetermined).
Result<HandEyeResult> hand_eye_calibration(const std::vector<Transform>& tracker_from_marker,
                                           const std::vector<Transform>& camera_from_target);

}  // namespace nav::calibration
