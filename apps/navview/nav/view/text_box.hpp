#pragma once
// navview's text: one font and size for captions, the health band and panel, and the help.
#include <string_view>

#include <opencv2/core/mat.hpp>

namespace nav::view {

/// Height of one line of text in a box, in pixels.
inline constexpr int kTextLinePx = 17;

/// `text` in white with its baseline's left end at `baseline_left`.
void draw_text(cv::Mat& image, std::string_view text, cv::Point baseline_left);

/// `text` in white on a filled box of `background` whose lower left corner is `bottom_left`;
/// returns the box's height.
int draw_text_box(cv::Mat& image, std::string_view text, cv::Point bottom_left, const cv::Scalar& background);

}  // namespace nav::view
