#include "nav/ultrasound/tumour_tracker.hpp"

#include <opencv2/core/utility.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>

namespace nav::ultrasound {
namespace {

double median_of(const cv::Mat& image) {
  int histogram[256] = {};
  for (int r = 0; r < image.rows; ++r) {
    const std::uint8_t* row = image.ptr<std::uint8_t>(r);
    for (int c = 0; c < image.cols; ++c) ++histogram[row[c]];
  }
  const long half = static_cast<long>(image.total()) / 2;
  long seen = 0;
  for (int level = 0; level < 256; ++level) {
    seen += histogram[level];
    if (seen > half) return level;
  }
  return 255.0;
}

}  // namespace

TumourTracker::TumourTracker(const TumourTrackerOptions& options) : options_(options) { cv::setNumThreads(0); }

TumourDetection TumourTracker::update(const std::uint8_t* pixels, std::uint32_t width_px, std::uint32_t height_px) {
  const cv::Mat frame(static_cast<int>(height_px), static_cast<int>(width_px), CV_8U,
                      const_cast<std::uint8_t*>(pixels));
  cv::Mat smooth;
  cv::GaussianBlur(frame, smooth, cv::Size(0, 0), options_.smoothing_sigma_px);
  const double median = median_of(smooth);
  cv::Mat dark;
  cv::threshold(smooth, dark, options_.dark_fraction * median, 255, cv::THRESH_BINARY_INV);
  cv::Mat labels, stats, centroids;
  const int count = cv::connectedComponentsWithStats(dark, labels, stats, centroids, 8, CV_32S);

  TumourDetection best;
  double best_score = 0.0;
  const double min_area = M_PI * options_.min_radius_px * options_.min_radius_px;
  const double max_area = M_PI * options_.max_radius_px * options_.max_radius_px;
  for (int label = 1; label < count; ++label) {
    const int left = stats.at<int>(label, cv::CC_STAT_LEFT);
    const int top = stats.at<int>(label, cv::CC_STAT_TOP);
    const int box_width = stats.at<int>(label, cv::CC_STAT_WIDTH);
    const int box_height = stats.at<int>(label, cv::CC_STAT_HEIGHT);
    const double area = stats.at<int>(label, cv::CC_STAT_AREA);
    const bool touches_border =
        left == 0 || top == 0 || left + box_width >= frame.cols || top + box_height >= frame.rows;
    if (touches_border || area < min_area || area > max_area) continue;
    const double u = centroids.at<double>(label, 0);
    const double v = centroids.at<double>(label, 1);
    if (last_.found && std::hypot(u - last_.u_px, v - last_.v_px) > options_.max_step_px) continue;
    // Roundness: the region's area against the disc of its bounding box's mean diameter.
    const double diameter = 0.5 * (box_width + box_height);
    const double roundness = std::min(1.0, area / (M_PI * 0.25 * diameter * diameter));
    const double inside = cv::mean(smooth, labels == label)[0];
    const double contrast = std::clamp(1.0 - inside / std::max(median, 1.0), 0.0, 1.0);
    const double score = roundness * contrast * std::sqrt(area);
    if (score <= best_score) continue;
    best_score = score;
    best = {true, u, v, std::sqrt(area / M_PI), roundness * contrast};
  }
  last_ = best;
  return best;
}

Eigen::Vector3d image_point_in_world(double u_px, double v_px, double spacing_x_m, double spacing_y_m,
                                     const Eigen::Isometry3d& probe_from_image,
                                     const Eigen::Isometry3d& world_from_probe) {
  return world_from_probe * (probe_from_image * Eigen::Vector3d(u_px * spacing_x_m, v_px * spacing_y_m, 0.0));
}

}  // namespace nav::ultrasound
