#include "nav/view/composite.hpp"

#include <cmath>
#include <cstdio>

#include <opencv2/imgproc.hpp>

#include "nav/view/frame_overlay.hpp"
#include "nav/view/health_panel.hpp"
#include "nav/view/palette.hpp"
#include "nav/view/text_box.hpp"

namespace nav::view {
namespace {

constexpr int kCaptionBaselinePx = 16;

void caption(cv::Mat& panel, const char* text) { draw_text(panel, text, {6, kCaptionBaselinePx}); }

/// "frame 12 | target 3 (rung 2, +50 ms): 1.2 mm off plane", or "frame 12 | not placed (no
/// probe pose, or no --scene)".
void caption_frame_panel(cv::Mat& panel, const DisplayInputs& inputs) {
  char text[160];
  int used = inputs.frame != nullptr ? std::snprintf(text, sizeof(text), "frame %llu",
                                                     static_cast<unsigned long long>(inputs.frame->sequence_number))
                                     : std::snprintf(text, sizeof(text), "waiting for ultrasound");
  const bool room = used > 0 && static_cast<std::size_t>(used) < sizeof(text);
  if (inputs.frame != nullptr && inputs.image_from_model == nullptr && room) {
    std::snprintf(text + used, sizeof(text) - static_cast<std::size_t>(used),
                  " | not placed (no probe pose, or no --scene)");
  } else if (inputs.frame != nullptr && inputs.prediction != nullptr && room) {
    std::snprintf(text + used, sizeof(text) - static_cast<std::size_t>(used),
                  " | target %u (rung %u, +%lld ms): %.1f mm off plane", inputs.prediction->target_id,
                  inputs.prediction->model_rung, static_cast<long long>(inputs.prediction->horizon_ns / kNsPerMs),
                  inputs.image_from_model->apply(inputs.prediction->position_m)[2] * 1e3);
  }
  caption(panel, text);
}

/// The distance from the needle's tip to the target (metres), or a negative value without both.
double tip_to_target_m(const DisplayInputs& inputs) {
  if (inputs.needle == nullptr || inputs.needle->point_count == 0 || inputs.prediction == nullptr) return -1.0;
  const dds::Vector3& tip = inputs.needle->shape_points_m[inputs.needle->point_count - 1];
  const dds::Vector3& target = inputs.prediction->position_m;
  return std::sqrt((tip[0] - target[0]) * (tip[0] - target[0]) + (tip[1] - target[1]) * (tip[1] - target[1]) +
                   (tip[2] - target[2]) * (tip[2] - target[2]));
}

/// "surface 4: 2194 vertices | needle 21 points, tip force 0.55 N | tip to target 12.3 mm"
void caption_surface_panel(cv::Mat& panel, const DisplayInputs& inputs) {
  char text[200];
  int used = inputs.surface != nullptr ? std::snprintf(text, sizeof(text), "surface %u: %u vertices",
                                                       inputs.surface->surface_id, inputs.surface->vertex_count)
                                       : std::snprintf(text, sizeof(text), "waiting for the surface");
  if (inputs.needle != nullptr && used > 0 && static_cast<std::size_t>(used) < sizeof(text)) {
    const dds::Vector3& f = inputs.needle->tip_force_n;
    used += std::snprintf(text + used, sizeof(text) - static_cast<std::size_t>(used),
                          " | needle %u points, tip force %.2f N", inputs.needle->point_count,
                          std::sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]));
  }
  if (const double distance_m = tip_to_target_m(inputs);
      distance_m >= 0.0 && used > 0 && static_cast<std::size_t>(used) < sizeof(text))
    std::snprintf(text + used, sizeof(text) - static_cast<std::size_t>(used), " | tip to target %.1f mm",
                  1e3 * distance_m);
  caption(panel, text);
}

/// The keyboard help in the 3-D panel's upper left, below its caption.
void draw_help(cv::Mat& panel) {
  int bottom_px = kCaptionBaselinePx + 6;
  for (std::string_view line : kViewHelpLines) {
    bottom_px += kTextLinePx;
    draw_text_box(panel, line, {4, bottom_px}, palette::kHelpBackground);
  }
}

/// "h: help" in the 3-D panel's upper right corner.
void draw_help_hint(cv::Mat& panel) {
  draw_text_box(panel, "h: help", {panel.cols - 64, kCaptionBaselinePx + 6 + kTextLinePx}, palette::kHelpBackground);
}

}  // namespace

Composer::Composer(const CompositeOptions& options, SurfaceTriangles surface_triangles)
    : options_(options),
      surface_triangles_(std::move(surface_triangles)),
      view_(options.view_azimuth_deg, options.view_elevation_deg) {}

const cv::Mat& Composer::render(const DisplayInputs& inputs, const dds::StationHealth* health) {
  const int height = options_.panel_height_px;
  const int frame_width = inputs.frame != nullptr
                              ? FramePanelMapping::for_frame(*inputs.frame, height).panel_width_px(*inputs.frame)
                              : height;
  canvas_.create(height, frame_width + height, CV_8UC3);
  cv::Mat frame_panel = canvas_(cv::Rect(0, 0, frame_width, height));
  cv::Mat surface_panel = canvas_(cv::Rect(frame_width, 0, height, height));

  if (inputs.frame != nullptr) {
    draw_frame_panel(frame_panel, *inputs.frame, inputs.needle, inputs.prediction, inputs.image_from_model);
  } else {
    frame_panel.setTo(cv::Scalar(0, 0, 0));
  }
  if (inputs.surface != nullptr && !camera_fitted_) {
    fitted_camera_ = fit_camera(*inputs.surface, options_.view_azimuth_deg, options_.view_elevation_deg, height);
    camera_fitted_ = true;
  }
  if (camera_fitted_ && inputs.surface != nullptr) {
    const OrthoCamera camera =
        OrthoCamera::from_angles(fitted_camera_.look_at_m, view_.azimuth_deg(), view_.elevation_deg(),
                                 fitted_camera_.panel_px_per_m * view_.zoom(), height);
    painter_.draw(surface_panel, camera, *inputs.surface, surface_triangles_, inputs.needle, inputs.prediction);
  } else {
    surface_panel.setTo(palette::kSurfaceBackground);
  }
  if (options_.captions) {
    caption_frame_panel(frame_panel, inputs);
    caption_surface_panel(surface_panel, inputs);
  }
  if (view_.help_shown()) {
    draw_help(surface_panel);
  } else if (options_.interactive) {
    draw_help_hint(surface_panel);
  }
  if (health != nullptr) {
    draw_status_band(canvas_, *health);
    draw_input_lines(surface_panel, *health);
  }
  return canvas_;
}

}  // namespace nav::view
