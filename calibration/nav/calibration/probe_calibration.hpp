#pragma once
// Ultrasound probe spatial calibration: the transform probe_from_image from the image plane to
// the probe's tracked marker, and the pixel spacing. Pixel (u, v) is the image point
// (u * spacing_x, v * spacing_y, 0); with a = sx R e_x and b = sy R e_y the mapping
// q = u a + v b + t is linear, so both calibrations below start from linear least squares made
// rigid (the nearest rotation to [a/|a|, b/|b|, a x b]); the N-wire fit then re-solves the rigid
// map itself (rotation, translation, spacing).
#include <cstddef>
#include <vector>

#include "nav/calibration/rigid_transform.hpp"
#include "nav/core/error.hpp"

namespace nav::calibration {

/// A probe calibration and how well it fits its points.
struct ProbeCalibration {
  Transform probe_from_image = Transform::Identity();
  Eigen::Vector2d spacing_m = Eigen::Vector2d::Ones();  ///< along a row (u), along a column (v)
  double rms_residual_m = 0.0;
  std::size_t points = 0;  ///< inliers used
  std::size_t outliers = 0;
};

/// The probe-frame point of pixel (u, v).
Eigen::Vector3d probe_point(const ProbeCalibration& calibration, const Eigen::Vector2d& pixel);

/// A pixel and the same point known in the probe frame (metres).
struct ImageProbePoint {
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();
  Eigen::Vector3d probe_m = Eigen::Vector3d::Zero();
};

/// Settings shared by the probe calibrations.
struct ProbeCalibrationOptions {
  std::size_t min_points = 6;
  /// A point whose residual exceeds this multiple of the median residual is an outlier.
  double outlier_median_factor = 4.0;
  /// Smallest accepted ratio of the design matrix's singular values (collinear pixels, or
  /// poses without rotation, leave the calibration undetermined).
  double min_inverse_condition = 1e-6;
};

/// Fits the calibration to pixel / probe-point pairs (N-wire phantoms give these). Errors:
/// too few points, collinear pixels.
Result<ProbeCalibration> fit_probe_calibration(const std::vector<ImageProbePoint>& points,
                                               const ProbeCalibrationOptions& options = {});

/// One sighting of a fixed point target: the tracked probe pose and the target's pixel.
struct TargetSighting {
  Transform tracker_from_probe = Transform::Identity();
  Eigen::Vector2d pixel = Eigen::Vector2d::Zero();
};

/// A point-target calibration: the calibration and the target's position in the tracker.
struct PointTargetCalibration {
  ProbeCalibration calibration;
  Eigen::Vector3d target_in_tracker_m = Eigen::Vector3d::Zero();
};

/// Calibrates from sightings of one fixed point (a bead or a crossed-wire point): solves
/// u a + v b + t - R_i^T p = -R_i^T t_i for a, b, t and the target p. Errors: too few
/// sightings, too little pose variety.
Result<PointTargetCalibration> point_target_calibration(const std::vector<TargetSighting>& sightings,
                                                        const ProbeCalibrationOptions& options = {});

/// Distances between the calibration's probe points and the known ones (validation), over all
/// of them, and as PLUS reports them (its ReprojectionError3DStatistics): the mean and the
/// standard deviation (over the count) of the lowest 95 %.
struct ProbeValidation {
  double mean_error_m = 0.0;
  double rms_error_m = 0.0;
  double max_error_m = 0.0;
  double lowest95_mean_error_m = 0.0;
  double lowest95_sd_error_m = 0.0;
  std::size_t points = 0;
};

/// The reprojection errors of `calibration` on independent points.
ProbeValidation validate_probe_calibration(const ProbeCalibration& calibration,
                                           const std::vector<ImageProbePoint>& points);

}  // namespace nav::calibration
