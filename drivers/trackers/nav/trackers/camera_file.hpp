#pragma once
// The camera intrinsics file that `navtool calib camera` writes: a comment line, then
// "fx_px fy_px cx_px cy_px k1 k2 p1 p2 k3 rms_px" (pixel centres at integers; Brown-Conrady
// distortion as OpenCV's). Init-time code.
#include <string>

#include "nav/core/error.hpp"
#include "nav/trackers/apriltag_tracker.hpp"

namespace nav::trackers {

/// The intrinsics in the file at `path`. Errors name the file and line: missing, fewer than
/// nine numbers, a non-finite one, a focal length that is not positive.
Result<CameraIntrinsics> read_camera_intrinsics(const std::string& path);

}  // namespace nav::trackers
