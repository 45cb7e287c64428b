#include "nav/calibration/temporal_calibration_signals.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>

namespace nav::calibration {

std::optional<double> bright_line_row_px(const std::uint8_t* pixels, int width_px, int height_px,
                                         const std::array<int, 4>& clip_xywh, double threshold_fraction,
                                         int min_columns) {
  const int x0 = std::max(0, clip_xywh[0]), y0 = std::max(0, clip_xywh[1]);
  const int x1 = std::min(width_px, clip_xywh[0] + clip_xywh[2]), y1 = std::min(height_px, clip_xywh[1] + clip_xywh[3]);
  if (x1 <= x0 || y1 <= y0) return std::nullopt;
  int brightest = 0;
  for (int y = y0; y < y1; ++y) {
    for (int x = x0; x < x1; ++x) brightest = std::max<int>(brightest, pixels[y * width_px + x]);
  }
  const double threshold = threshold_fraction * brightest;
  if (brightest == 0) return std::nullopt;
  // Weighted least squares of row = slope * column + intercept over the columns' centroids.
  Eigen::Matrix2d normal = Eigen::Matrix2d::Zero();
  Eigen::Vector2d right = Eigen::Vector2d::Zero();
  int columns = 0;
  for (int x = x0; x < x1; ++x) {
    double weight = 0.0, moment = 0.0;
    for (int y = y0; y < y1; ++y) {
      const double value = pixels[y * width_px + x];
      if (value <= threshold) continue;
      weight += value;
      moment += value * y;
    }
    if (weight <= 0.0) continue;
    ++columns;
    const Eigen::Vector2d row(x, 1.0);
    normal += weight * row * row.transpose();
    right += weight * (moment / weight) * row;
  }
  if (columns < min_columns) return std::nullopt;
  const Eigen::Vector2d line = normal.ldlt().solve(right);
  return line(0) * 0.5 * (x0 + x1 - 1) + line(1);
}

TimedSignal principal_motion(const std::vector<double>& times_s, const std::vector<Eigen::Vector3d>& positions,
                             double from_s, double to_s) {
  TimedSignal signal;
  std::vector<Eigen::Vector3d> inside;
  for (std::size_t i = 0; i < times_s.size(); ++i) {
    if (times_s[i] < from_s || times_s[i] > to_s) continue;
    signal.times_s.push_back(times_s[i]);
    inside.push_back(positions[i]);
  }
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& p : inside) mean += p / static_cast<double>(inside.size());
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const Eigen::Vector3d& p : inside) scatter += (p - mean) * (p - mean).transpose();
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(scatter);
  const Eigen::Vector3d direction = solver.eigenvectors().col(2);  // largest eigenvalue last
  for (const Eigen::Vector3d& p : inside) signal.values.push_back(direction.dot(p - mean));
  return signal;
}

}  // namespace nav::calibration
