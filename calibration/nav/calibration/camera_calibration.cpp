#include "nav/calibration/camera_calibration.hpp"

#include <Eigen/Dense>
#include <cmath>
#include <string>

#include "nav/calibration/point_registration.hpp"

namespace nav::calibration {
namespace {

/// Hartley normalisation: centroid to the origin, mean distance sqrt(2).
Eigen::Matrix3d normaliser(const std::vector<Eigen::Vector2d>& points) {
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const auto& p : points) mean += p / static_cast<double>(points.size());
  double distance = 0.0;
  for (const auto& p : points) distance += (p - mean).norm() / static_cast<double>(points.size());
  const double scale = std::sqrt(2.0) / std::max(distance, 1e-300);
  Eigen::Matrix3d t;
  t << scale, 0.0, -scale * mean.x(), 0.0, scale, -scale * mean.y(), 0.0, 0.0, 1.0;
  return t;
}

/// Zhang's v_ij of homography h (columns i and j).
Eigen::Matrix<double, 6, 1> zhang_v(const Eigen::Matrix3d& h, int i, int j) {
  Eigen::Matrix<double, 6, 1> v;
  v << h(0, i) * h(0, j), h(0, i) * h(1, j) + h(1, i) * h(0, j), h(1, i) * h(1, j),
      h(2, i) * h(0, j) + h(0, i) * h(2, j), h(2, i) * h(1, j) + h(1, i) * h(2, j), h(2, i) * h(2, j);
  return v;
}

/// Board pose from a homography and the intrinsics K.
Transform pose_from_homography(const Eigen::Matrix3d& k, const Eigen::Matrix3d& h) {
  const Eigen::Matrix3d k_inverse = k.inverse();
  const double lambda = 1.0 / (k_inverse * h.col(0)).norm();
  Eigen::Matrix3d r;
  r.col(0) = lambda * k_inverse * h.col(0);
  r.col(1) = lambda * k_inverse * h.col(1);
  r.col(2) = r.col(0).cross(r.col(1));
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(r, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Transform pose = Transform::Identity();
  pose.linear() = svd.matrixU() * svd.matrixV().transpose();
  pose.translation() = lambda * k_inverse * h.col(2);
  if (pose.translation().z() < 0.0) {  // the board is in front of the camera
    pose.linear().col(0) *= -1.0;
    pose.linear().col(1) *= -1.0;
    pose.translation() *= -1.0;
  }
  return pose;
}

/// The model's parameters: fx, fy, cx, cy, k1, k2, p1, p2, k3, then per view a rotation
/// vector and translation.
using Parameters = Eigen::VectorXd;
constexpr Eigen::Index kCameraParameters = 9;

LensDistortion lens_of(const Parameters& p) { return {p(4), p(5), p(6), p(7), p(8)}; }

Eigen::VectorXd residuals(const std::vector<PlanarView>& views, const Parameters& p) {
  Eigen::Index count = 0;
  for (const auto& view : views) count += 2 * static_cast<Eigen::Index>(view.board_points_m.size());
  Eigen::VectorXd r(count);
  Eigen::Index row = 0;
  const LensDistortion lens = lens_of(p);
  for (std::size_t v = 0; v < views.size(); ++v) {
    const Eigen::Index base = kCameraParameters + 6 * static_cast<Eigen::Index>(v);
    const Eigen::Vector3d rotation_vector = p.segment<3>(base);
    const Eigen::Matrix3d rotation =
        rotation_vector.norm() > 0.0
            ? Eigen::AngleAxisd(rotation_vector.norm(), rotation_vector.normalized()).toRotationMatrix()
            : Eigen::Matrix3d::Identity();
    for (std::size_t i = 0; i < views[v].board_points_m.size(); ++i) {
      const Eigen::Vector2d& b = views[v].board_points_m[i];
      const Eigen::Vector3d c = rotation * Eigen::Vector3d(b.x(), b.y(), 0.0) + p.segment<3>(base + 3);
      const Eigen::Vector2d seen = distort(lens, Eigen::Vector2d(c.x() / c.z(), c.y() / c.z()));
      r(row++) = p(0) * seen.x() + p(2) - views[v].image_points_px[i].x();
      r(row++) = p(1) * seen.y() + p(3) - views[v].image_points_px[i].y();
    }
  }
  return r;
}

}  // namespace

Result<Eigen::Matrix3d> fit_homography(const PlanarView& view) {
  const std::size_t n = view.board_points_m.size();
  if (n < 4 || view.image_points_px.size() != n)
    return Error{.message = "a view needs >= 4 matched points", .field = "view"};
  std::vector<Eigen::Vector3d> board3;
  for (const auto& b : view.board_points_m) board3.emplace_back(b.x(), b.y(), 0.0);
  if (point_spread(board3)(1) < 1e-6) return Error{.message = "the view's board points are collinear", .field = "view"};
  const Eigen::Matrix3d tb = normaliser(view.board_points_m);
  const Eigen::Matrix3d ti = normaliser(view.image_points_px);
  Eigen::MatrixXd a(2 * static_cast<Eigen::Index>(n), 9);
  for (std::size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d x = tb * view.board_points_m[i].homogeneous();
    const Eigen::Vector3d u = ti * view.image_points_px[i].homogeneous();
    const auto row = 2 * static_cast<Eigen::Index>(i);
    a.row(row) << x.transpose(), 0.0, 0.0, 0.0, -u.x() * x.transpose();
    a.row(row + 1) << 0.0, 0.0, 0.0, x.transpose(), -u.y() * x.transpose();
  }
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(a, Eigen::ComputeFullV);
  const Eigen::VectorXd h = svd.matrixV().col(8);
  Eigen::Matrix3d normalised;
  normalised << h(0), h(1), h(2), h(3), h(4), h(5), h(6), h(7), h(8);
  const Eigen::Matrix3d homography = ti.inverse() * normalised * tb;
  return Eigen::Matrix3d(homography / homography(2, 2));
}

Result<CameraCalibration> calibrate_camera(const std::vector<PlanarView>& views, const CameraModelOptions& options) {
  if (views.size() < 3)
    return Error{.message = "too few views: " + std::to_string(views.size()) + " < 3", .field = "views"};
  std::vector<Eigen::Matrix3d> homographies;
  Eigen::MatrixXd v(2 * static_cast<Eigen::Index>(views.size()), 6);
  for (std::size_t i = 0; i < views.size(); ++i) {
    Result<Eigen::Matrix3d> h = fit_homography(views[i]);
    if (!h) return Error{.message = h.error().message, .field = "view " + std::to_string(i)};
    homographies.push_back(h.value());
    v.row(2 * static_cast<Eigen::Index>(i)) = zhang_v(h.value(), 0, 1).transpose();
    v.row(2 * static_cast<Eigen::Index>(i) + 1) = (zhang_v(h.value(), 0, 0) - zhang_v(h.value(), 1, 1)).transpose();
  }
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(v, Eigen::ComputeFullV);
  const Eigen::VectorXd b = svd.matrixV().col(5);
  const double b11 = b(0), b12 = b(1), b22 = b(2), b13 = b(3), b23 = b(4), b33 = b(5);
  const double denominator = b11 * b22 - b12 * b12;
  const double v0 = (b12 * b13 - b11 * b23) / denominator;
  const double lambda = b33 - (b13 * b13 + v0 * (b12 * b13 - b11 * b23)) / b11;
  if (!(lambda / b11 > 0.0) || !(lambda * b11 / denominator > 0.0) ||
      svd.singularValues()(4) < 1e-9 * svd.singularValues()(0)) {
    return Error{.message = "the views do not constrain the intrinsics (boards too alike in orientation)",
                 .field = "views"};
  }
  const double alpha = std::sqrt(lambda / b11);
  const double beta = std::sqrt(lambda * b11 / denominator);
  const double gamma = -b12 * alpha * alpha * beta / lambda;
  const double u0 = gamma * v0 / beta - b13 * alpha * alpha / lambda;
  Eigen::Matrix3d k;
  k << alpha, 0.0, u0, 0.0, beta, v0, 0.0, 0.0, 1.0;  // skew dropped: square pixels, no skew
  Parameters p = Parameters::Zero(kCameraParameters + 6 * static_cast<Eigen::Index>(views.size()));
  p.head<4>() << alpha, beta, u0, v0;
  for (std::size_t i = 0; i < views.size(); ++i) {
    const Transform pose = pose_from_homography(k, homographies[i]);
    const Eigen::AngleAxisd rotation(pose.rotation());
    const auto base = kCameraParameters + 6 * static_cast<Eigen::Index>(i);
    p.segment<3>(base) = rotation.angle() * rotation.axis();
    p.segment<3>(base + 3) = pose.translation();
  }
  // Levenberg-Marquardt over the free parameters, numerical Jacobian.
  std::vector<Eigen::Index> free;
  for (Eigen::Index j = 0; j < p.size(); ++j) {
    const bool distortion = j >= 4 && j < kCameraParameters;
    if (!distortion || (options.estimate_distortion && j < 8) || (options.estimate_k3 && j == 8)) free.push_back(j);
  }
  const auto free_count = static_cast<Eigen::Index>(free.size());
  double damping = 1e-3;
  Eigen::VectorXd r0 = residuals(views, p);
  for (int iteration = 0; iteration < 100; ++iteration) {
    Eigen::MatrixXd jacobian(r0.size(), free_count);
    for (Eigen::Index f = 0; f < free_count; ++f) {
      const Eigen::Index j = free[static_cast<std::size_t>(f)];
      const double step = 1e-6 * std::max(1.0, std::abs(p(j)));
      Parameters plus = p, minus = p;
      plus(j) += step;
      minus(j) -= step;
      jacobian.col(f) = (residuals(views, plus) - residuals(views, minus)) / (2.0 * step);
    }
    const Eigen::MatrixXd normal = jacobian.transpose() * jacobian;
    const Eigen::VectorXd gradient = jacobian.transpose() * r0;
    Eigen::MatrixXd damped = normal;
    damped.diagonal() += damping * normal.diagonal();
    const Eigen::VectorXd update = damped.ldlt().solve(-gradient);
    Parameters trial = p;
    for (Eigen::Index f = 0; f < free_count; ++f) trial(free[static_cast<std::size_t>(f)]) += update(f);
    const Eigen::VectorXd r_trial = residuals(views, trial);
    if (r_trial.squaredNorm() < r0.squaredNorm()) {
      p = trial;
      r0 = r_trial;
      damping = std::max(damping * 0.1, 1e-9);
      if (update.norm() < 1e-12 * p.norm()) break;
    } else {
      damping *= 10.0;
      if (damping > 1e9) break;  // no step lowers the error: converged
    }
  }
  CameraCalibration result;
  result.fx_px = p(0);
  result.fy_px = p(1);
  result.cx_px = p(2);
  result.cy_px = p(3);
  result.distortion = lens_of(p);
  result.rms_reprojection_px = std::sqrt(r0.squaredNorm() / static_cast<double>(r0.size() / 2));
  for (std::size_t i = 0; i < views.size(); ++i) {
    const auto base = kCameraParameters + 6 * static_cast<Eigen::Index>(i);
    const Eigen::Vector3d rv = p.segment<3>(base);
    Transform pose = Transform::Identity();
    if (rv.norm() > 0.0) pose.linear() = Eigen::AngleAxisd(rv.norm(), rv.normalized()).toRotationMatrix();
    pose.translation() = p.segment<3>(base + 3);
    result.camera_from_board.push_back(pose);
  }
  return result;
}

}  // namespace nav::calibration
