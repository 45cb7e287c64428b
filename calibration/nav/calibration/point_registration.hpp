#pragma once
// Rigid registration of paired points (Horn / Umeyama, no scaling): the transform that best
// maps fiducials located in one frame (e.g. the preoperative model) onto the same fiducials
// located in another (e.g. the tracker), with the fiducial registration error (FRE), and the
// target registration error (TRE) of points that took no part in the fit.
#include <vector>

#include "nav/calibration/rigid_transform.hpp"
#include "nav/core/error.hpp"

namespace nav::calibration {

/// A rigid registration: target_from_source and its RMS fiducial registration error.
struct PointRegistration {
  Transform target_from_source = Transform::Identity();
  double fre_rms_m = 0.0;
};

/// Registers `source[i]` onto `target[i]`. Errors: fewer than 3 pairs, different counts,
/// collinear points (the rotation about their line is undetermined).
Result<PointRegistration> register_points(const std::vector<Eigen::Vector3d>& source,
                                          const std::vector<Eigen::Vector3d>& target);

/// RMS distance between `registration` applied to `source_targets` and their true positions.
double target_registration_error_m(const Transform& target_from_source,
                                   const std::vector<Eigen::Vector3d>& source_targets,
                                   const std::vector<Eigen::Vector3d>& true_targets);

/// The singular values (descending) of the centred point cloud's 3x3 scatter, normalised by
/// the largest: (1, s2, s3); s2 ~ 0 means collinear, s3 ~ 0 coplanar.
Eigen::Vector3d point_spread(const std::vector<Eigen::Vector3d>& points);

}  // namespace nav::calibration
