#include "nav/view/drawing.hpp"

#include <cmath>

#include <opencv2/imgproc.hpp>

namespace nav::view {

cv::Point to_fixed_point(const cv::Point2d& point) {
  constexpr double kScale = 1 << kSubpixelBits;
  return {static_cast<int>(std::lround(point.x * kScale)), static_cast<int>(std::lround(point.y * kScale))};
}

void draw_segment(cv::Mat& image, const cv::Point2d& from, const cv::Point2d& to, const cv::Scalar& colour,
                  int thickness_px) {
  cv::line(image, to_fixed_point(from), to_fixed_point(to), colour, thickness_px, cv::LINE_AA, kSubpixelBits);
}

void draw_marker(cv::Mat& image, const cv::Point2d& centre, double radius_px, const cv::Scalar& colour) {
  const cv::Point fixed = to_fixed_point(centre);
  const int radius = static_cast<int>(std::lround(radius_px * (1 << kSubpixelBits)));
  cv::circle(image, fixed, radius + (1 << kSubpixelBits), cv::Scalar(0, 0, 0), cv::FILLED, cv::LINE_AA, kSubpixelBits);
  cv::circle(image, fixed, radius, colour, cv::FILLED, cv::LINE_AA, kSubpixelBits);
}

}  // namespace nav::view
