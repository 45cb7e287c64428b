#pragma once
// Camera intrinsics from views of a planar board (Zhang 2000): a homography per view (DLT on
// normalised points), the closed-form intrinsics from the homographies' constraints, the
// board poses, then Levenberg-Marquardt refinement of the camera model (fx, fy, cx, cy, no
// skew; Brown-Conrady lens distortion k1, k2, p1, p2 and optionally k3, lens_distortion.hpp)
// and every pose on the reprojection error. Pixel centres at integers.
#include <vector>

#include "nav/calibration/lens_distortion.hpp"
#include "nav/calibration/rigid_transform.hpp"
#include "nav/core/error.hpp"

namespace nav::calibration {

/// One view: board points (metres, on the board's z = 0 plane) and where they were seen.
struct PlanarView {
  std::vector<Eigen::Vector2d> board_points_m;
  std::vector<Eigen::Vector2d> image_points_px;
};

/// Calibrated intrinsics and lens distortion, the board pose of each view and the
/// reprojection RMS.
struct CameraCalibration {
  double fx_px = 0.0;
  double fy_px = 0.0;
  double cx_px = 0.0;
  double cy_px = 0.0;
  LensDistortion distortion;
  double rms_reprojection_px = 0.0;
  std::vector<Transform> camera_from_board;
};

/// Which distortion coefficients the refinement estimates (the others stay 0). k3 needs
/// views that reach the image corners; without them it trades off against k1 and k2.
struct CameraModelOptions {
  bool estimate_distortion = true;  ///< k1, k2, p1, p2
  bool estimate_k3 = false;
};

/// Calibrates from >= 3 views of >= 4 points each. Errors: too few views or points, views
/// that do not constrain the intrinsics (e.g. boards all parallel to the image).
Result<CameraCalibration> calibrate_camera(const std::vector<PlanarView>& views,
                                           const CameraModelOptions& options = {});

/// The homography mapping board (x, y, 1) to image pixels, from >= 4 non-collinear points.
Result<Eigen::Matrix3d> fit_homography(const PlanarView& view);

}  // namespace nav::calibration
