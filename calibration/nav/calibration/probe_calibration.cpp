#include "nav/calibration/probe_calibration.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>

namespace nav::calibration {
namespace {

/// Solves the least-squares system, or says it is too ill-conditioned.
Result<Eigen::VectorXd> solve(const Eigen::MatrixXd& a, const Eigen::VectorXd& b,
                              const ProbeCalibrationOptions& options, const char* why) {
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(a, Eigen::ComputeThinU | Eigen::ComputeThinV);
  const auto& singular = svd.singularValues();
  if (singular(singular.size() - 1) < options.min_inverse_condition * singular(0))
    return Error{.message = why, .field = "points"};
  return Eigen::VectorXd(svd.solve(b));
}

/// The rigid calibration nearest to the linear map q = u a + v b + t.
ProbeCalibration make_rigid(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& t) {
  ProbeCalibration calibration;
  calibration.spacing_m = {a.norm(), b.norm()};
  Eigen::Matrix3d axes;
  axes << a.normalized(), b.normalized(), a.cross(b).normalized();
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(axes, Eigen::ComputeFullU | Eigen::ComputeFullV);
  calibration.probe_from_image.linear() = svd.matrixU() * svd.matrixV().transpose();
  calibration.probe_from_image.translation() = t;
  return calibration;
}

std::vector<double> residuals(const ProbeCalibration& calibration, const std::vector<ImageProbePoint>& points) {
  std::vector<double> result;
  for (const ImageProbePoint& point : points)
    result.push_back((probe_point(calibration, point.pixel) - point.probe_m).norm());
  return result;
}

double median(std::vector<double> values) {
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(values.size() / 2), values.end());
  return values[values.size() / 2];
}

double rms(const std::vector<double>& values) {
  double sum = 0.0;
  for (const double value : values) sum += value * value;
  return std::sqrt(sum / static_cast<double>(values.size()));
}

Result<ProbeCalibration> fit_once(const std::vector<ImageProbePoint>& points, const ProbeCalibrationOptions& options) {
  if (points.size() < options.min_points)
    return Error{.message = "too few points for a probe calibration", .field = "points"};
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(3 * static_cast<Eigen::Index>(points.size()), 9);
  Eigen::VectorXd b(3 * static_cast<Eigen::Index>(points.size()));
  for (std::size_t i = 0; i < points.size(); ++i) {
    const auto row = 3 * static_cast<Eigen::Index>(i);
    a.block<3, 3>(row, 0) = points[i].pixel.x() * Eigen::Matrix3d::Identity();
    a.block<3, 3>(row, 3) = points[i].pixel.y() * Eigen::Matrix3d::Identity();
    a.block<3, 3>(row, 6) = Eigen::Matrix3d::Identity();
    b.segment<3>(row) = points[i].probe_m;
  }
  const auto x = solve(a, b, options, "the pixels are collinear: the image plane is undetermined");
  if (!x) return x.error();
  ProbeCalibration calibration = make_rigid(x.value().segment<3>(0), x.value().segment<3>(3), x.value().segment<3>(6));
  calibration.points = points.size();
  calibration.rms_residual_m = rms(residuals(calibration, points));
  return calibration;
}

}  // namespace

Eigen::Vector3d probe_point(const ProbeCalibration& calibration, const Eigen::Vector2d& pixel) {
  return calibration.probe_from_image *
         Eigen::Vector3d(pixel.x() * calibration.spacing_m.x(), pixel.y() * calibration.spacing_m.y(), 0.0);
}

Result<ProbeCalibration> fit_probe_calibration(const std::vector<ImageProbePoint>& points,
                                               const ProbeCalibrationOptions& options) {
  auto first = fit_once(points, options);
  if (!first) return first;
  const std::vector<double> errors = residuals(first.value(), points);
  const double limit = options.outlier_median_factor * median(errors);
  std::vector<ImageProbePoint> inliers;
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (errors[i] <= limit) inliers.push_back(points[i]);
  }
  auto refit = fit_once(inliers, options);
  if (!refit) return refit;
  refit.value().outliers = points.size() - inliers.size();
  return refit;
}

Result<PointTargetCalibration> point_target_calibration(const std::vector<TargetSighting>& sightings,
                                                        const ProbeCalibrationOptions& options) {
  if (sightings.size() < options.min_points)
    return Error{.message = "too few sightings for a point-target calibration", .field = "sightings"};
  Eigen::MatrixXd a = Eigen::MatrixXd::Zero(3 * static_cast<Eigen::Index>(sightings.size()), 12);
  Eigen::VectorXd b(3 * static_cast<Eigen::Index>(sightings.size()));
  for (std::size_t i = 0; i < sightings.size(); ++i) {
    const auto row = 3 * static_cast<Eigen::Index>(i);
    const Eigen::Matrix3d rotation_t = sightings[i].tracker_from_probe.linear().transpose();
    a.block<3, 3>(row, 0) = sightings[i].pixel.x() * Eigen::Matrix3d::Identity();
    a.block<3, 3>(row, 3) = sightings[i].pixel.y() * Eigen::Matrix3d::Identity();
    a.block<3, 3>(row, 6) = Eigen::Matrix3d::Identity();
    a.block<3, 3>(row, 9) = -rotation_t;
    b.segment<3>(row) = -rotation_t * sightings[i].tracker_from_probe.translation();
  }
  const auto x = solve(a, b, options, "the sightings lack pose variety (rotate and move the probe over the target)");
  if (!x) return x.error();
  PointTargetCalibration result;
  result.calibration = make_rigid(x.value().segment<3>(0), x.value().segment<3>(3), x.value().segment<3>(6));
  result.target_in_tracker_m = x.value().segment<3>(9);
  std::vector<ImageProbePoint> points;
  for (const TargetSighting& sighting : sightings) {
    points.push_back({sighting.pixel, sighting.tracker_from_probe.inverse() * result.target_in_tracker_m});
  }
  result.calibration.points = points.size();
  result.calibration.rms_residual_m = rms(residuals(result.calibration, points));
  return result;
}

ProbeValidation validate_probe_calibration(const ProbeCalibration& calibration,
                                           const std::vector<ImageProbePoint>& points) {
  ProbeValidation validation;
  if (points.empty()) return validation;
  const std::vector<double> errors = residuals(calibration, points);
  for (const double error : errors) {
    validation.mean_error_m += error / static_cast<double>(errors.size());
    validation.max_error_m = std::max(validation.max_error_m, error);
  }
  validation.rms_error_m = rms(errors);
  validation.points = errors.size();
  return validation;
}

}  // namespace nav::calibration
