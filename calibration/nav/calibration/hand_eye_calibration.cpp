#include "nav/calibration/hand_eye_calibration.hpp"

#include <Eigen/SVD>
#include <cmath>
#include <string>

namespace nav::calibration {
namespace {

Eigen::Vector3d rotation_vector(const Eigen::Matrix3d& rotation) {
  const Eigen::AngleAxisd angle_axis(rotation);
  return angle_axis.angle() * angle_axis.axis();
}

/// A motion pair: A = T_marker_j^-1 T_marker_i and B = T_camera_j T_camera_i^-1 satisfy AX = XB.
struct Motion {
  Transform a;
  Transform b;
};

}  // namespace

Result<HandEyeResult> hand_eye_calibration(const std::vector<Transform>& tracker_from_marker,
                                           const std::vector<Transform>& camera_from_target) {
  if (tracker_from_marker.size() != camera_from_target.size()) {
    return Error{.message = "marker and camera pose counts differ", .field = "poses"};
  }
  if (tracker_from_marker.size() < 3) {
    return Error{.message = "too few poses: " + std::to_string(tracker_from_marker.size()) + " < 3", .field = "poses"};
  }
  std::vector<Motion> motions;
  for (std::size_t i = 0; i < tracker_from_marker.size(); ++i) {
    for (std::size_t j = i + 1; j < tracker_from_marker.size(); ++j) {
      motions.push_back({tracker_from_marker[j].inverse() * tracker_from_marker[i],
                         camera_from_target[j] * camera_from_target[i].inverse()});
    }
  }
  // Rotation: R_A = R_X R_B R_X^T, so the rotation vectors satisfy alpha = R_X beta.
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (const Motion& motion : motions) {
    covariance += rotation_vector(motion.b.rotation()) * rotation_vector(motion.a.rotation()).transpose();
  }
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(covariance, Eigen::ComputeFullU | Eigen::ComputeFullV);
  if (svd.singularValues()(1) < 1e-6 * svd.singularValues()(0) || svd.singularValues()(0) < 1e-12) {
    return Error{.message = "the motions' rotation axes are all parallel (or there is no rotation): X is undetermined",
                 .field = "poses"};
  }
  Eigen::Matrix3d sign = Eigen::Matrix3d::Identity();
  sign(2, 2) = (svd.matrixV() * svd.matrixU().transpose()).determinant() < 0.0 ? -1.0 : 1.0;
  const Eigen::Matrix3d rotation = svd.matrixV() * sign * svd.matrixU().transpose();
  // Translation: (R_A - I) t_X = R_X t_B - t_A, stacked over all motions.
  const auto rows = static_cast<Eigen::Index>(3 * motions.size());
  Eigen::MatrixXd lhs(rows, 3);
  Eigen::VectorXd rhs(rows);
  for (std::size_t k = 0; k < motions.size(); ++k) {
    const auto row = static_cast<Eigen::Index>(3 * k);
    lhs.block<3, 3>(row, 0) = motions[k].a.rotation() - Eigen::Matrix3d::Identity();
    rhs.segment<3>(row) = rotation * motions[k].b.translation() - motions[k].a.translation();
  }
  HandEyeResult result;
  result.marker_from_camera.linear() = rotation;
  result.marker_from_camera.translation() = lhs.colPivHouseholderQr().solve(rhs);
  result.motions = motions.size();
  double rotation_squares = 0.0;
  double translation_squares = 0.0;
  for (const Motion& motion : motions) {
    const Transform ax = motion.a * result.marker_from_camera;
    const Transform xb = result.marker_from_camera * motion.b;
    rotation_squares += std::pow(rotation_angle_rad(ax.rotation(), xb.rotation()), 2);
    translation_squares += (ax.translation() - xb.translation()).squaredNorm();
  }
  result.rms_rotation_residual_rad = std::sqrt(rotation_squares / static_cast<double>(motions.size()));
  result.rms_translation_residual_m = std::sqrt(translation_squares / static_cast<double>(motions.size()));
  return result;
}

}  // namespace nav::calibration
