#include "nav/calibration/nwire_segmentation.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>

namespace nav::calibration {
namespace {

struct Dot {
  Eigen::Vector2d centre_px;
  double weight = 0.0;  // summed squared filtered intensity
};

struct Triple {
  std::array<std::size_t, 3> dots;  // indices, left to right
  double angle_rad = 0.0;
  double error_px = 0.0;
};

/// The frame with what is not a dot taken away, as PLUS's fiducial segmentation does: in turn
/// along rows, the two diagonals and columns, the structures longer than the bar (a white
/// top-hat: the frame less its opening by a line of 2 bar + 1 pixels), which removes the
/// reverberation tails under the wires and bar echoes; then specks smaller than the disc (an
/// opening); then everything below the threshold fraction of the range left.
cv::Mat dots_only(const cv::Mat& image, const NWireSegmentationOptions& options) {
  const int bar = options.bar_half_length_px, length = 2 * bar + 1;
  cv::Mat working = image.clone(), opened;
  const cv::Mat diagonal = cv::Mat::eye(length, length, CV_8U);
  cv::Mat anti_diagonal;
  cv::flip(diagonal, anti_diagonal, 1);
  for (const cv::Mat& line :
       {cv::Mat(cv::Mat::ones(1, length, CV_8U)), diagonal, cv::Mat(cv::Mat::ones(length, 1, CV_8U)), anti_diagonal}) {
    cv::morphologyEx(working, opened, cv::MORPH_OPEN, line);
    cv::subtract(working, opened, working);  // saturates at 0
  }
  const int disc = 2 * options.opening_radius_px + 1;
  cv::morphologyEx(working, working, cv::MORPH_OPEN, cv::getStructuringElement(cv::MORPH_ELLIPSE, {disc, disc}));
  double low = 0.0, high = 0.0;
  cv::minMaxLoc(working, &low, &high);
  const double threshold = low + std::floor(options.threshold_fraction * (high - low) + 0.5);
  cv::threshold(working, working, threshold - 1.0, 0, cv::THRESH_TOZERO);  // keeps values >= threshold
  return working;
}

std::vector<Dot> find_dots(const cv::Mat& image, const NWireSegmentationOptions& options) {
  const cv::Mat filtered = dots_only(image, options);
  cv::Mat bright;
  cv::threshold(filtered, bright, 0, 255, cv::THRESH_BINARY);
  cv::Mat labels, stats, centroids;
  const int count = cv::connectedComponentsWithStats(bright, labels, stats, centroids, 8, CV_32S);
  std::vector<Dot> dots;
  for (int label = 1; label < count; ++label) {
    const int left = stats.at<int>(label, cv::CC_STAT_LEFT), top = stats.at<int>(label, cv::CC_STAT_TOP);
    const int width = stats.at<int>(label, cv::CC_STAT_WIDTH), height = stats.at<int>(label, cv::CC_STAT_HEIGHT);
    const double area = stats.at<int>(label, cv::CC_STAT_AREA);
    const double elongation = static_cast<double>(std::max(width, height)) / std::min(width, height);
    if (area < options.min_dot_area_px || area > options.max_dot_area_px || elongation > options.max_dot_elongation)
      continue;
    Dot dot;
    Eigen::Vector2d sum = Eigen::Vector2d::Zero();
    for (int y = top; y < top + height; ++y) {
      for (int x = left; x < left + width; ++x) {
        if (labels.at<int>(y, x) != label) continue;
        const double value = filtered.at<std::uint8_t>(y, x);
        const double w = value * value;  // squared: the dot's peak outweighs its skirt
        sum += w * Eigen::Vector2d(x, y);
        dot.weight += w;
      }
    }
    if (dot.weight <= 0.0) continue;
    dot.centre_px = sum / dot.weight;
    dots.push_back(dot);
  }
  std::sort(dots.begin(), dots.end(), [](const Dot& a, const Dot& b) { return a.weight > b.weight; });
  if (dots.size() > options.max_candidates) dots.resize(options.max_candidates);
  std::sort(dots.begin(), dots.end(), [](const Dot& a, const Dot& b) { return a.centre_px.x() < b.centre_px.x(); });
  return dots;
}

std::vector<Triple> collinear_triples(const std::vector<Dot>& dots, const NWireSegmentationOptions& options) {
  std::vector<Triple> triples;
  for (std::size_t i = 0; i < dots.size(); ++i) {
    for (std::size_t k = i + 2; k < dots.size(); ++k) {
      const Eigen::Vector2d a = dots[i].centre_px, c = dots[k].centre_px;
      const Eigen::Vector2d direction = c - a;
      if (direction.norm() < options.min_line_length_px) continue;
      const double angle = std::atan2(direction.y(), direction.x());
      if (std::abs(angle) > options.max_line_angle_rad) continue;
      const Eigen::Vector2d unit = direction.normalized();
      for (std::size_t j = i + 1; j < k; ++j) {
        const Eigen::Vector2d offset = dots[j].centre_px - a;
        const double along = offset.dot(unit);
        const double error = std::abs(offset.x() * unit.y() - offset.y() * unit.x());
        if (error > options.collinear_tolerance_px || along <= 0.0 || along >= direction.norm()) continue;
        triples.push_back({{i, j, k}, angle, error});
      }
    }
  }
  std::sort(triples.begin(), triples.end(), [](const Triple& a, const Triple& b) { return a.error_px < b.error_px; });
  if (triples.size() > 60) triples.resize(60);
  return triples;
}

/// Depth-first search for `count` disjoint, nearly parallel triples of least total error.
void search(const std::vector<Triple>& triples, std::size_t count, std::size_t from, std::vector<std::size_t>& chosen,
            double error, const NWireSegmentationOptions& options, std::vector<std::size_t>& best, double& best_error) {
  if (chosen.size() == count) {
    if (error < best_error) {
      best_error = error;
      best = chosen;
    }
    return;
  }
  for (std::size_t t = from; t < triples.size(); ++t) {
    bool compatible = true;
    for (const std::size_t other : chosen) {
      const Triple& a = triples[t];
      const Triple& b = triples[other];
      compatible = compatible && std::abs(a.angle_rad - b.angle_rad) <= options.max_angle_difference_rad;
      for (const std::size_t x : a.dots) {
        for (const std::size_t y : b.dots) compatible = compatible && x != y;
      }
    }
    if (!compatible) continue;
    chosen.push_back(t);
    search(triples, count, t + 1, chosen, error + triples[t].error_px, options, best, best_error);
    chosen.pop_back();
  }
}

}  // namespace

std::optional<std::vector<NWireLine>> find_nwire_dots(const std::uint8_t* pixels, int width_px, int height_px,
                                                      std::size_t line_count, const NWireSegmentationOptions& options) {
  const cv::Mat frame(height_px, width_px, CV_8U, const_cast<std::uint8_t*>(pixels));
  const cv::Rect clip =
      cv::Rect(options.clip_xywh[0], options.clip_xywh[1], options.clip_xywh[2], options.clip_xywh[3]) &
      cv::Rect(0, 0, width_px, height_px);
  if (clip.area() == 0) return std::nullopt;
  std::vector<Dot> dots = find_dots(frame(clip), options);
  for (Dot& dot : dots) dot.centre_px += Eigen::Vector2d(clip.x, clip.y);
  const std::vector<Triple> triples = collinear_triples(dots, options);
  std::vector<std::size_t> chosen, best;
  double best_error = std::numeric_limits<double>::infinity();
  search(triples, line_count, 0, chosen, 0.0, options, best, best_error);
  if (best.size() != line_count) return std::nullopt;
  std::vector<NWireLine> lines;
  for (const std::size_t t : best) {
    const auto& indices = triples[t].dots;
    lines.push_back({dots[indices[0]].centre_px, dots[indices[1]].centre_px, dots[indices[2]].centre_px});
  }
  std::sort(lines.begin(), lines.end(), [](const NWireLine& a, const NWireLine& b) {
    return a[0].y() + a[1].y() + a[2].y() < b[0].y() + b[1].y() + b[2].y();
  });
  return lines;
}

}  // namespace nav::calibration
