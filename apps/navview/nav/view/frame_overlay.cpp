#include "nav/view/frame_overlay.hpp"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

#include "nav/view/drawing.hpp"
#include "nav/view/palette.hpp"

namespace nav::view {
namespace {

constexpr int kFrameNeedleThicknessPx = 3;
constexpr int kEllipseThicknessPx = 2;
constexpr double kFrameTargetRadiusPx = 4.0;

/// The radius, in standard deviations, of the 2-D Gaussian's kEllipseProbability contour.
double ellipse_radius_sigmas() { return std::sqrt(-2.0 * std::log(1.0 - kEllipseProbability)); }

}  // namespace

dds::Vector3 ImageFromModel::apply(const dds::Vector3& point_m) const {
  dds::Vector3 image{};
  for (std::size_t r = 0; r < 3; ++r)
    image[r] = rotation[3 * r] * point_m[0] + rotation[3 * r + 1] * point_m[1] + rotation[3 * r + 2] * point_m[2] +
               translation_m[r];
  return image;
}

dds::Covariance3 ImageFromModel::rotate(const dds::Covariance3& covariance_m2) const {
  dds::Covariance3 rotated{};
  for (std::size_t r = 0; r < 3; ++r)
    for (std::size_t c = 0; c < 3; ++c)
      for (std::size_t i = 0; i < 3; ++i)
        for (std::size_t j = 0; j < 3; ++j)
          rotated[3 * r + c] += rotation[3 * r + i] * covariance_m2[3 * i + j] * rotation[3 * c + j];
  return rotated;
}

FramePanelMapping FramePanelMapping::for_frame(const dds::UltrasoundFrame& frame, int panel_height_px) {
  return {frame.pixel_spacing_m, static_cast<double>(panel_height_px) / static_cast<double>(frame.height_px)};
}

cv::Point2d FramePanelMapping::to_panel(const dds::Vector3& point_m) const {
  // A frame pixel i covers [i - 0.5, i + 0.5]; scaling keeps the panel's edges on the frame's.
  const auto scale = [&](double frame_px) { return (frame_px + 0.5) * panel_px_per_frame_px - 0.5; };
  return {scale(point_m[0] / pixel_spacing_m[0]), scale(point_m[1] / pixel_spacing_m[1])};
}

int FramePanelMapping::panel_width_px(const dds::UltrasoundFrame& frame) const {
  return std::max(1, static_cast<int>(std::lround(frame.width_px * panel_px_per_frame_px)));
}

PanelEllipse uncertainty_ellipse(const FramePanelMapping& mapping, const dds::TargetPrediction& prediction,
                                 const ImageFromModel& image_from_model) {
  // The in-plane covariance in panel pixels squared: S C S with S = diag(panel px per metre).
  const dds::Covariance3 covariance = image_from_model.rotate(prediction.covariance_m2);
  const double sx = mapping.panel_px_per_frame_px / mapping.pixel_spacing_m[0];
  const double sy = mapping.panel_px_per_frame_px / mapping.pixel_spacing_m[1];
  const double a = covariance[0] * sx * sx;
  const double b = 0.5 * (covariance[1] + covariance[3]) * sx * sy;
  const double c = covariance[4] * sy * sy;
  // Eigen-decomposition of the symmetric [[a, b], [b, c]].
  const double mean = 0.5 * (a + c);
  const double spread = std::hypot(0.5 * (a - c), b);
  const double k = ellipse_radius_sigmas();
  PanelEllipse ellipse;
  ellipse.centre_px = mapping.to_panel(image_from_model.apply(prediction.position_m));
  ellipse.half_axis_major_px = k * std::sqrt(std::max(0.0, mean + spread));
  ellipse.half_axis_minor_px = k * std::sqrt(std::max(0.0, mean - spread));
  ellipse.major_axis_angle_deg = 0.5 * std::atan2(2.0 * b, a - c) * 180.0 / M_PI;
  return ellipse;
}

void draw_frame_panel(cv::Mat& panel, const dds::UltrasoundFrame& frame, const dds::NeedleState* needle,
                      const dds::TargetPrediction* prediction, const ImageFromModel* image_from_model) {
  // The pixels are only read: OpenCV's header does not copy them.
  const cv::Mat gray(static_cast<int>(frame.height_px), static_cast<int>(frame.width_px), CV_8UC1,
                     const_cast<std::uint8_t*>(frame.pixels.data()));
  cv::Mat scaled;
  cv::resize(gray, scaled, panel.size(), 0.0, 0.0, panel.rows < gray.rows ? cv::INTER_AREA : cv::INTER_LINEAR);
  cv::cvtColor(scaled, panel, cv::COLOR_GRAY2BGR);

  if (image_from_model == nullptr) return;
  const FramePanelMapping mapping = FramePanelMapping::for_frame(frame, panel.rows);
  const auto to_panel = [&](const dds::Vector3& model_m) { return mapping.to_panel(image_from_model->apply(model_m)); };
  if (needle != nullptr) {
    for (std::uint32_t i = 1; i < needle->point_count; ++i) {
      draw_segment(panel, to_panel(needle->shape_points_m[i - 1]), to_panel(needle->shape_points_m[i]),
                   palette::kNeedle, kFrameNeedleThicknessPx);
    }
  }
  if (prediction != nullptr) {
    const PanelEllipse ellipse = uncertainty_ellipse(mapping, *prediction, *image_from_model);
    constexpr double kFixed = 1 << kSubpixelBits;
    const cv::Size axes(static_cast<int>(std::lround(ellipse.half_axis_major_px * kFixed)),
                        static_cast<int>(std::lround(ellipse.half_axis_minor_px * kFixed)));
    cv::ellipse(panel, to_fixed_point(ellipse.centre_px), axes, ellipse.major_axis_angle_deg, 0.0, 360.0,
                palette::kUncertainty, kEllipseThicknessPx, cv::LINE_AA, kSubpixelBits);
    draw_marker(panel, ellipse.centre_px, kFrameTargetRadiusPx, palette::kTarget);
  }
}

}  // namespace nav::view
