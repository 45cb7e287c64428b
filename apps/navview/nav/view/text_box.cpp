#include "nav/view/text_box.hpp"

#include <string>

#include <opencv2/imgproc.hpp>

#include "nav/view/palette.hpp"

namespace nav::view {
namespace {

constexpr int kFont = cv::FONT_HERSHEY_SIMPLEX;
constexpr double kScale = 0.45;
constexpr int kPaddingPx = 3;

}  // namespace

void draw_text(cv::Mat& image, std::string_view text, cv::Point baseline_left) {
  cv::putText(image, std::string(text), baseline_left, kFont, kScale, palette::kText, 1, cv::LINE_AA);
}

int draw_text_box(cv::Mat& image, std::string_view text, cv::Point bottom_left, const cv::Scalar& background) {
  int baseline = 0;
  const cv::Size size = cv::getTextSize(std::string(text), kFont, kScale, 1, &baseline);
  const cv::Rect box(bottom_left.x, bottom_left.y - kTextLinePx, size.width + 2 * kPaddingPx, kTextLinePx);
  cv::rectangle(image, box, background, cv::FILLED);
  draw_text(image, text, {bottom_left.x + kPaddingPx, bottom_left.y - kPaddingPx - baseline / 2});
  return kTextLinePx;
}

}  // namespace nav::view
