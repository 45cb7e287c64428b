#include "nav/view/composite.hpp"

#include <cmath>
#include <cstdio>

#include <opencv2/imgproc.hpp>

#include "nav/core/health_names.hpp"
#include "nav/dds/sample_fault.hpp"
#include "nav/view/frame_overlay.hpp"
#include "nav/view/palette.hpp"

namespace nav::view {
namespace {

constexpr double kCaptionScale = 0.45;
constexpr int kCaptionBaselinePx = 16;

void caption(cv::Mat& panel, const char* text) {
  cv::putText(panel, text, cv::Point(6, kCaptionBaselinePx), cv::FONT_HERSHEY_SIMPLEX, kCaptionScale, palette::kText, 1,
              cv::LINE_AA);
}

/// "frame 12 | target 3 (rung 2, +50 ms): 1.2 mm off plane"
void caption_frame_panel(cv::Mat& panel, const DisplayInputs& inputs) {
  char text[160];
  int used = inputs.frame != nullptr ? std::snprintf(text, sizeof(text), "frame %llu",
                                                     static_cast<unsigned long long>(inputs.frame->sequence_number))
                                     : std::snprintf(text, sizeof(text), "waiting for ultrasound");
  if (inputs.prediction != nullptr && used > 0 && static_cast<std::size_t>(used) < sizeof(text)) {
    std::snprintf(text + used, sizeof(text) - static_cast<std::size_t>(used),
                  " | target %u (rung %u, +%lld ms): %.1f mm off plane", inputs.prediction->target_id,
                  inputs.prediction->model_rung, static_cast<long long>(inputs.prediction->horizon_ns / kNsPerMs),
                  inputs.prediction->position_m[2] * 1e3);
  }
  caption(panel, text);
}

/// "surface 4: 2194 vertices | needle 21 points, tip force 0.55 N"
void caption_surface_panel(cv::Mat& panel, const DisplayInputs& inputs) {
  char text[160];
  int used = inputs.surface != nullptr ? std::snprintf(text, sizeof(text), "surface %u: %u vertices",
                                                       inputs.surface->surface_id, inputs.surface->vertex_count)
                                       : std::snprintf(text, sizeof(text), "waiting for the surface");
  if (inputs.needle != nullptr && used > 0 && static_cast<std::size_t>(used) < sizeof(text)) {
    const dds::Vector3& f = inputs.needle->tip_force_n;
    std::snprintf(text + used, sizeof(text) - static_cast<std::size_t>(used), " | needle %u points, tip force %.2f N",
                  inputs.needle->point_count, std::sqrt(f[0] * f[0] + f[1] * f[1] + f[2] * f[2]));
  }
  caption(panel, text);
}

constexpr int kStatusBandPx = 22;

const char* mode_name(dds::StationMode mode) {
  switch (mode) {
    case dds::StationMode::starting:
      return "starting";
    case dds::StationMode::running:
      return "running";
    case dds::StationMode::degraded:
      return "DEGRADED";
    case dds::StationMode::stopped:
      return "stopped";
  }
  return "in an unknown mode";
}

/// "station running | healthy | dropped at the boundary: none" across the canvas's bottom, with
/// each input in trouble ("needle: bad_sample stale_input") after the station's flags.
void draw_status_band(cv::Mat& canvas, const StationStatus& status) {
  const dds::StationHealth& health = *status.health;
  bool healthy = health.mode == dds::StationMode::running && health.flags == 0;
  for (const std::uint32_t flags : health.input_flags) healthy = healthy && flags == 0;
  cv::Mat band = canvas(cv::Rect(0, canvas.rows - kStatusBandPx, canvas.cols, kStatusBandPx));
  band.setTo(healthy ? palette::kStatusHealthy : palette::kStatusDegraded);
  const std::string flags = health_flag_names(health.flags);
  std::string text = std::string("station ") + mode_name(health.mode) + " | " + (flags.empty() ? "healthy" : flags);
  for (std::size_t i = 0; i < dds::kStationInputCount; ++i)  // the inputs in trouble, each with its own flags
    if (health.input_flags[i] != 0)
      text += std::string(" | ") + dds::station_input_name(static_cast<dds::StationInput>(i)) + ": " +
              health_flag_names(health.input_flags[i]);
  text += " | dropped at the boundary: " + status.drops;
  cv::putText(band, text, cv::Point(6, kStatusBandPx - 7), cv::FONT_HERSHEY_SIMPLEX, kCaptionScale, palette::kText, 1,
              cv::LINE_AA);
}

}  // namespace

Composer::Composer(const CompositeOptions& options, SurfaceTriangles surface_triangles)
    : options_(options), surface_triangles_(std::move(surface_triangles)) {}

const cv::Mat& Composer::render(const DisplayInputs& inputs, const StationStatus* status) {
  const int height = options_.panel_height_px;
  const int frame_width = inputs.frame != nullptr
                              ? FramePanelMapping::for_frame(*inputs.frame, height).panel_width_px(*inputs.frame)
                              : height;
  canvas_.create(height, frame_width + height, CV_8UC3);
  cv::Mat frame_panel = canvas_(cv::Rect(0, 0, frame_width, height));
  cv::Mat surface_panel = canvas_(cv::Rect(frame_width, 0, height, height));

  if (inputs.frame != nullptr) {
    draw_frame_panel(frame_panel, *inputs.frame, inputs.needle, inputs.prediction);
  } else {
    frame_panel.setTo(cv::Scalar(0, 0, 0));
  }
  if (inputs.surface != nullptr && !camera_fitted_) {
    camera_ = fit_camera(*inputs.surface, options_.view_azimuth_deg, options_.view_elevation_deg, height);
    camera_fitted_ = true;
  }
  if (camera_fitted_ && inputs.surface != nullptr) {
    painter_.draw(surface_panel, camera_, *inputs.surface, surface_triangles_, inputs.needle, inputs.prediction);
  } else {
    surface_panel.setTo(palette::kSurfaceBackground);
  }
  if (options_.captions) {
    caption_frame_panel(frame_panel, inputs);
    caption_surface_panel(surface_panel, inputs);
  }
  if (status != nullptr && status->health != nullptr) draw_status_band(canvas_, *status);
  return canvas_;
}

}  // namespace nav::view
