#pragma once
// The tag size and pinhole camera of the AprilTag tests' rendered images (header-only: shared
// by the programs of tests/trackers).
#include "nav/trackers/apriltag_tracker.hpp"

namespace nav::testing {

/// The printed tags' edge.
inline constexpr double kTagSize_m = 0.05;
/// A 640 x 480 pinhole camera with a 600 px focal length, centred.
inline const trackers::CameraIntrinsics kCamera{600.0, 600.0, 319.5, 239.5};

}  // namespace nav::testing
