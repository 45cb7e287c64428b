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

/// The rigid calibration re-solved from `start`: in turn the rotation and translation for the
/// spacing (Umeyama on the scaled pixels) and the spacing and translation for the rotation
/// (linear least squares), while the residual falls. The snapped linear fit keeps the
/// translation and spacing of a map that was not rigid; this fits the rigid one itself.
ProbeCalibration refine_rigid(const ProbeCalibration& start, const std::vector<ImageProbePoint>& points) {
  const auto n = static_cast<Eigen::Index>(points.size());
  Eigen::Matrix3Xd targets(3, n);
  for (Eigen::Index i = 0; i < n; ++i) targets.col(i) = points[static_cast<std::size_t>(i)].probe_m;
  ProbeCalibration best = start;
  best.rms_residual_m = rms(residuals(start, points));
  ProbeCalibration next = best;
  for (int round = 0; round < 100; ++round) {
    Eigen::Matrix3Xd scaled(3, n);
    for (Eigen::Index i = 0; i < n; ++i) {
      const Eigen::Vector2d& pixel = points[static_cast<std::size_t>(i)].pixel;
      scaled.col(i) = Eigen::Vector3d(pixel.x() * next.spacing_m.x(), pixel.y() * next.spacing_m.y(), 0.0);
    }
    next.probe_from_image.matrix() = Eigen::umeyama(scaled, targets, false);
    const Eigen::Matrix3d rotation = next.probe_from_image.linear();
    Eigen::MatrixXd a(3 * n, 5);
    Eigen::VectorXd b(3 * n);
    for (Eigen::Index i = 0; i < n; ++i) {
      const Eigen::Vector2d& pixel = points[static_cast<std::size_t>(i)].pixel;
      a.block<3, 1>(3 * i, 0) = pixel.x() * rotation.col(0);
      a.block<3, 1>(3 * i, 1) = pixel.y() * rotation.col(1);
      a.block<3, 3>(3 * i, 2) = Eigen::Matrix3d::Identity();
      b.segment<3>(3 * i) = targets.col(i);
    }
    const Eigen::VectorXd x = a.colPivHouseholderQr().solve(b);
    next.spacing_m = x.head<2>();
    next.probe_from_image.translation() = x.tail<3>();
    next.rms_residual_m = rms(residuals(next, points));
    if (!(next.rms_residual_m < best.rms_residual_m * (1.0 - 1e-9))) break;
    best = next;
  }
  return best;
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
  ProbeCalibration calibration =
      refine_rigid(make_rigid(x.value().segment<3>(0), x.value().segment<3>(3), x.value().segment<3>(6)), points);
  calibration.points = points.size();
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
  // PLUS's statistic: the lowest 95 % of the errors (rounded), their mean and their standard
  // deviation over the count (IGSIO's igsioMath::ComputePercentile and ComputeMeanAndStdev).
  std::vector<double> sorted = errors;
  std::sort(sorted.begin(), sorted.end());
  sorted.resize(
      std::max<std::size_t>(1, static_cast<std::size_t>(std::lround(0.95 * static_cast<double>(sorted.size())))));
  double sum = 0.0, sum_squares = 0.0;
  for (const double error : sorted) sum += error, sum_squares += error * error;
  const double kept = static_cast<double>(sorted.size());
  validation.lowest95_mean_error_m = sum / kept;
  validation.lowest95_sd_error_m = std::sqrt(
      std::max(0.0, sum_squares / kept - validation.lowest95_mean_error_m * validation.lowest95_mean_error_m));
  return validation;
}

}  // namespace nav::calibration
