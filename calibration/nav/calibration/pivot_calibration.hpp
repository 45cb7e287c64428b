#pragma once
// Pivot calibration of a needle: the marker is swung about the tip resting in a divot, and
// the tip offset in the marker frame and the pivot point in the tracker frame come from one
// linear least-squares system R_i t_tip + p_i = p_pivot, with outlier rejection, the RMS
// residual and a conditioning check on the angular spread of the poses.
#include <cstddef>
#include <vector>

#include "nav/calibration/rigid_transform.hpp"
#include "nav/core/error.hpp"

namespace nav::calibration {

/// Settings of pivot_calibration.
struct PivotOptions {
  std::size_t min_poses = 8;
  /// The poses must turn at least this far from their mean orientation (radians).
  double min_angular_spread_rad = 0.26;  // 15 degrees
  /// A pose whose residual exceeds this multiple of the median residual is an outlier.
  double outlier_median_factor = 4.0;
  /// The largest ratio of the system's singular values accepted (rotations about one axis only
  /// leave the tip's position along it undetermined).
  double max_condition_number = 1e4;
};

/// The result of a pivot calibration.
struct PivotResult {
  Eigen::Vector3d tip_in_marker_m = Eigen::Vector3d::Zero();     // t_tip: tip in the marker frame
  Eigen::Vector3d pivot_in_tracker_m = Eigen::Vector3d::Zero();  // the divot in the tracker frame
  double rms_residual_m = 0.0;                                   // over the inliers
  std::size_t inliers = 0;
  std::size_t outliers = 0;
  double angular_spread_rad = 0.0;
  double condition_number = 0.0;
};

/// Calibrates from the tracked poses tracker_from_marker. Errors: too few poses, too little
/// rotation, an ill-conditioned set, too many outliers.
Result<PivotResult> pivot_calibration(const std::vector<Transform>& tracker_from_marker,
                                      const PivotOptions& options = {});

}  // namespace nav::calibration
