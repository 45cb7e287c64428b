#pragma once
// Sub-pixel drawing helpers over OpenCV's fixed-point primitives, shared by both panels.
#include <opencv2/core/mat.hpp>

namespace nav::view {

/// Fractional bits of the fixed-point coordinates given to OpenCV's drawing functions.
inline constexpr int kSubpixelBits = 4;

/// `point` in OpenCV's fixed-point coordinates with kSubpixelBits fractional bits.
cv::Point to_fixed_point(const cv::Point2d& point);

/// An anti-aliased line of `thickness_px` from `from` to `to`.
void draw_segment(cv::Mat& image, const cv::Point2d& from, const cv::Point2d& to, const cv::Scalar& colour,
                  int thickness_px);

/// A filled disc of `radius_px` with a dark rim, so it stands out on any background.
void draw_marker(cv::Mat& image, const cv::Point2d& centre, double radius_px, const cv::Scalar& colour);

}  // namespace nav::view
