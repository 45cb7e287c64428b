#include "nav/calibration/point_registration.hpp"

#include <Eigen/SVD>
#include <cmath>
#include <string>

namespace nav::calibration {
namespace {

Eigen::Vector3d centroid(const std::vector<Eigen::Vector3d>& points) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const auto& point : points) sum += point;
  return sum / static_cast<double>(points.size());
}

}  // namespace

Eigen::Vector3d point_spread(const std::vector<Eigen::Vector3d>& points) {
  const Eigen::Vector3d mean = centroid(points);
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const auto& point : points) scatter += (point - mean) * (point - mean).transpose();
  const Eigen::Vector3d sigma = Eigen::JacobiSVD<Eigen::Matrix3d>(scatter).singularValues();
  return sigma(0) > 0.0 ? Eigen::Vector3d(sigma / sigma(0)) : Eigen::Vector3d::Zero();
}

Result<PointRegistration> register_points(const std::vector<Eigen::Vector3d>& source,
                                          const std::vector<Eigen::Vector3d>& target) {
  if (source.size() != target.size())
    return Error{.message = "source and target point counts differ", .field = "points"};
  if (source.size() < 3)
    return Error{.message = "too few points: " + std::to_string(source.size()) + " < 3", .field = "points"};
  if (point_spread(source)(1) < 1e-8 || point_spread(target)(1) < 1e-8) {
    return Error{.message = "the points are collinear: the rotation about their line is undetermined",
                 .field = "points"};
  }
  const Eigen::Vector3d source_mean = centroid(source);
  const Eigen::Vector3d target_mean = centroid(target);
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (std::size_t i = 0; i < source.size(); ++i) {
    covariance += (source[i] - source_mean) * (target[i] - target_mean).transpose();
  }
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(covariance, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d sign = Eigen::Matrix3d::Identity();
  sign(2, 2) = (svd.matrixV() * svd.matrixU().transpose()).determinant() < 0.0 ? -1.0 : 1.0;
  PointRegistration registration;
  registration.target_from_source.linear() = svd.matrixV() * sign * svd.matrixU().transpose();
  registration.target_from_source.translation() = target_mean - registration.target_from_source.linear() * source_mean;
  registration.fre_rms_m = target_registration_error_m(registration.target_from_source, source, target);
  return registration;
}

double target_registration_error_m(const Transform& target_from_source,
                                   const std::vector<Eigen::Vector3d>& source_targets,
                                   const std::vector<Eigen::Vector3d>& true_targets) {
  double sum_squares = 0.0;
  for (std::size_t i = 0; i < source_targets.size(); ++i) {
    sum_squares += (target_from_source * source_targets[i] - true_targets[i]).squaredNorm();
  }
  return std::sqrt(sum_squares / static_cast<double>(source_targets.size()));
}

}  // namespace nav::calibration
