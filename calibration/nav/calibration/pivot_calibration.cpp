#include "nav/calibration/pivot_calibration.hpp"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <string>

namespace nav::calibration {
namespace {

/// The largest angle between a pose's orientation and the (sign-aligned) mean quaternion.
double angular_spread_rad(const std::vector<Transform>& poses) {
  const Eigen::Quaterniond first(poses.front().rotation());
  Eigen::Vector4d sum = Eigen::Vector4d::Zero();
  for (const Transform& pose : poses) {
    Eigen::Quaterniond q(pose.rotation());
    if (q.dot(first) < 0.0) q.coeffs() = -q.coeffs();
    sum += q.coeffs();
  }
  const Eigen::Quaterniond mean(Eigen::Vector4d(sum.normalized()));
  double spread = 0.0;
  for (const Transform& pose : poses) {
    spread = std::max(spread, rotation_angle_rad(mean.toRotationMatrix(), pose.rotation()));
  }
  return spread;
}

struct Fit {
  Eigen::Matrix<double, 6, 1> solution;
  double condition_number;
};

Fit solve(const std::vector<Transform>& poses, const std::vector<bool>& use) {
  const auto rows = static_cast<Eigen::Index>(3 * std::count(use.begin(), use.end(), true));
  Eigen::MatrixXd a(rows, 6);
  Eigen::VectorXd b(rows);
  Eigen::Index row = 0;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    if (!use[i]) continue;
    a.block<3, 3>(row, 0) = poses[i].rotation();
    a.block<3, 3>(row, 3) = -Eigen::Matrix3d::Identity();
    b.segment<3>(row) = -poses[i].translation();
    row += 3;
  }
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(a, Eigen::ComputeThinU | Eigen::ComputeThinV);
  const auto& sigma = svd.singularValues();
  return {svd.solve(b), sigma(0) / std::max(sigma(5), 1e-300)};
}

}  // namespace

Result<PivotResult> pivot_calibration(const std::vector<Transform>& poses, const PivotOptions& options) {
  if (poses.size() < options.min_poses) {
    return Error{
        .message = "too few poses: " + std::to_string(poses.size()) + " < " + std::to_string(options.min_poses),
        .field = "poses"};
  }
  PivotResult result;
  result.angular_spread_rad = angular_spread_rad(poses);
  if (result.angular_spread_rad < options.min_angular_spread_rad) {
    return Error{.message = "not enough rotation in the pivot set: spread " +
                            std::to_string(result.angular_spread_rad * 180.0 / M_PI) + " deg < " +
                            std::to_string(options.min_angular_spread_rad * 180.0 / M_PI) + " deg",
                 .field = "poses"};
  }
  std::vector<bool> inlier(poses.size(), true);
  Fit fit{};
  std::vector<double> residuals(poses.size());
  for (int round = 0; round < 5; ++round) {
    fit = solve(poses, inlier);
    if (fit.condition_number > options.max_condition_number) {
      return Error{.message = "ill-conditioned pivot set (condition number " + std::to_string(fit.condition_number) +
                              "): the poses turn about one axis only",
                   .field = "poses"};
    }
    const Eigen::Vector3d tip = fit.solution.head<3>();
    const Eigen::Vector3d pivot = fit.solution.tail<3>();
    for (std::size_t i = 0; i < poses.size(); ++i) residuals[i] = (poses[i] * tip - pivot).norm();
    std::vector<double> sorted;
    for (std::size_t i = 0; i < poses.size(); ++i) {
      if (inlier[i]) sorted.push_back(residuals[i]);
    }
    std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2), sorted.end());
    const double threshold = options.outlier_median_factor * sorted[sorted.size() / 2];
    bool changed = false;
    for (std::size_t i = 0; i < poses.size(); ++i) {
      const bool keep = residuals[i] <= threshold;
      changed = changed || keep != inlier[i];
      inlier[i] = keep;
    }
    if (!changed) break;
    if (static_cast<std::size_t>(std::count(inlier.begin(), inlier.end(), true)) < options.min_poses) {
      return Error{
          .message = "too many outliers: fewer than " + std::to_string(options.min_poses) + " consistent poses",
          .field = "poses"};
    }
  }
  result.tip_in_marker_m = fit.solution.head<3>();
  result.pivot_in_tracker_m = fit.solution.tail<3>();
  result.condition_number = fit.condition_number;
  double sum_squares = 0.0;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    if (!inlier[i]) continue;
    ++result.inliers;
    sum_squares += residuals[i] * residuals[i];
  }
  result.outliers = poses.size() - result.inliers;
  result.rms_residual_m = std::sqrt(sum_squares / static_cast<double>(result.inliers));
  return result;
}

}  // namespace nav::calibration
