#pragma once
// A known scene for navview's pixel tests, shared by the renderer, headless and several-hosts
// tests: a flat gray frame, a straight needle, a target with an anisotropic uncertainty and a
// flat square surface, the panel pixels where each must appear, and helpers to find them in PNGs.
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <memory>
#include <set>
#include <string>

#include <opencv2/core/mat.hpp>

#include "nav/dds/samples.hpp"
#include "nav/view/composite.hpp"
#include "nav/view/palette.hpp"

namespace nav::view::testing {

inline constexpr int kPanelHeightPx = 200;
inline constexpr std::uint8_t kFrameGray = 60;

/// A 240 x 200 frame of one gray level, 1 mm per pixel along x and 0.5 mm along y, so that
/// with a 200-pixel panel one frame pixel is one panel pixel.
inline std::unique_ptr<dds::UltrasoundFrame> scene_frame() {
  auto frame = std::make_unique<dds::UltrasoundFrame>();
  frame->sequence_number = 12;
  frame->source_time_ns = 1000;
  frame->probe_tool_id = 2;
  frame->width_px = 240;
  frame->height_px = 200;
  frame->pixel_spacing_m = {1e-3, 0.5e-3};
  frame->depth_m = 0.1;
  for (std::size_t i = 0; i < frame->pixel_count(); ++i) frame->pixels[i] = kFrameGray;
  return frame;
}

/// A straight needle down column 30 of the frame, from row 20 to row 160.
inline dds::NeedleState scene_needle() {
  dds::NeedleState needle;
  needle.source_time_ns = 1000;
  needle.tool_id = 1;
  needle.point_count = 3;
  needle.shape_points_m[0] = {0.030, 0.010, 0.0};
  needle.shape_points_m[1] = {0.030, 0.045, 0.0};
  needle.shape_points_m[2] = {0.030, 0.080, 0.0};
  needle.tip_force_n = {0.0, 0.3, 0.4};
  return needle;
}

/// A target at frame pixel (120, 100), 4 mm sigma along x (4 px) and 3 mm along y (6 px).
inline dds::TargetPrediction scene_prediction() {
  dds::TargetPrediction prediction;
  prediction.source_time_ns = 1000;
  prediction.horizon_ns = 50 * kNsPerMs;
  prediction.target_id = 3;
  prediction.model_rung = 2;
  prediction.position_m = {0.120, 0.050, 0.0};
  prediction.covariance_m2 = {16e-6, 0, 0, 0, 9e-6, 0, 0, 0, 1e-6};
  return prediction;
}

/// The square [-0.1, 0.1]^2 at z = 0 as 4 vertices (two triangles: scene_triangles()).
inline std::unique_ptr<dds::DeformedSurface> scene_surface() {
  auto surface = std::make_unique<dds::DeformedSurface>();
  surface->source_time_ns = 1000;
  surface->surface_id = 4;
  surface->vertex_count = 4;
  surface->vertex_positions_m[0] = {-0.1f, -0.1f, 0.0f};
  surface->vertex_positions_m[1] = {0.1f, -0.1f, 0.0f};
  surface->vertex_positions_m[2] = {0.1f, 0.1f, 0.0f};
  surface->vertex_positions_m[3] = {-0.1f, 0.1f, 0.0f};
  return surface;
}

inline SurfaceTriangles scene_triangles() { return {{0, 1, 2}, {0, 2, 3}}; }

/// Composite options that view the square head-on (looking down -z) without captions.
inline CompositeOptions scene_options() {
  CompositeOptions options;
  options.panel_height_px = kPanelHeightPx;
  options.view_azimuth_deg = 0.0;
  options.view_elevation_deg = 0.0;
  options.captions = false;
  return options;
}

/// Where the scene must appear in the composite (x, y in composite pixels), by hand:
/// the 3-D panel starts at x = 240; its centre is 99.5; the square's bounding sphere
/// (radius 0.1 * sqrt 2) spans 90 % of 200 px, so 1 m is 90 / 0.14142 = 636.4 px.
namespace expected {
inline constexpr int kSurfacePanelX = 240;
inline constexpr double kSurfacePxPerM = 90.0 / 0.14142135623730951;
inline const cv::Point kNeedleTop{30, 20};
inline const cv::Point kNeedleBottom{30, 160};
inline const cv::Point kTarget{120, 100};
inline constexpr double kEllipseHalfAxisXPx = 2.4477468306808166 * 4.0;  // sqrt(-2 ln 0.05) sigma
inline constexpr double kEllipseHalfAxisYPx = 2.4477468306808166 * 6.0;
}  // namespace expected

/// True when `pixel` is within `tolerance` of `colour` in every channel.
inline bool near_colour(const cv::Vec3b& pixel, const cv::Scalar& colour, int tolerance = 40) {
  for (int c = 0; c < 3; ++c) {
    if (std::abs(static_cast<int>(pixel[c]) - static_cast<int>(colour[c])) > tolerance) return false;
  }
  return true;
}

/// Pixels of `image` exactly `colour`.
inline int pixels_of(const cv::Mat& image, const cv::Scalar& colour) {
  int count = 0;
  for (int y = 0; y < image.rows; ++y)
    for (int x = 0; x < image.cols; ++x) count += near_colour(image.at<cv::Vec3b>(y, x), colour, 0) ? 1 : 0;
  return count;
}

/// The surface's width in the 3-D panel (the kPanelHeightPx columns on the right of `image`)
/// along its middle row, which the scene's needle and target do not reach: the pixels that are
/// not the background.
inline int surface_width_px(const cv::Mat& image) {
  int count = 0;
  for (int x = image.cols - kPanelHeightPx; x < image.cols; ++x)
    count += near_colour(image.at<cv::Vec3b>(kPanelHeightPx / 2, x), palette::kSurfaceBackground, 0) ? 0 : 1;
  return count;
}

/// Writes scene_triangles() over the square's corners as an .obj file in millimetres,
/// for navview's --surface-mesh.
inline void write_scene_triangles_obj(const std::string& path) {
  std::ofstream(path) << "v -100 -100 0\nv 100 -100 0\nv 100 100 0\nv -100 100 0\nf 1 2 3\nf 1 3 4\n";
}

/// True when navview's `image` shows the test scene: frame, needle, target and surface
/// (the top rows hold the captions and are not looked at).
inline bool shows_scene(const cv::Mat& image) {
  if (image.rows != kPanelHeightPx || image.cols != expected::kSurfacePanelX + kPanelHeightPx) return false;
  const auto pixel = [&](double x, double y) { return image.at<cv::Vec3b>(static_cast<int>(y), static_cast<int>(x)); };
  const double surface_centre = 99.5;
  return near_colour(pixel(200, 150), cv::Scalar(kFrameGray, kFrameGray, kFrameGray), 0) &&
         near_colour(pixel(expected::kNeedleTop.x, 100), palette::kNeedle) &&
         near_colour(pixel(expected::kTarget.x, expected::kTarget.y), palette::kTarget, 0) &&
         near_colour(pixel(expected::kSurfacePanelX + surface_centre - 30, surface_centre + 30), palette::kSurface, 2);
}

/// The PNG files in `directory`, in name order (which is the order navview wrote them).
inline std::set<std::string> png_files(const std::filesystem::path& directory) {
  std::set<std::string> files;
  std::error_code ignored;
  for (const auto& entry : std::filesystem::directory_iterator(directory, ignored)) {
    if (entry.path().extension() == ".png") files.insert(entry.path().string());
  }
  return files;
}

}  // namespace nav::view::testing
