#include "nav/view/surface_view.hpp"

#include <algorithm>
#include <cmath>

#include <opencv2/imgproc.hpp>

#include "nav/view/drawing.hpp"
#include "nav/view/palette.hpp"

namespace nav::view {
namespace {

constexpr double kFitFraction = 0.9;
constexpr double kAmbientLight = 0.3;  // the rest is a headlight along the view direction
constexpr int kSurfaceNeedleThicknessPx = 2;
constexpr double kSurfaceTargetRadiusPx = 4.0;
constexpr double kTipRadiusPx = 3.0;   // the needle's tip when only the tip is known
constexpr double kForcePxPerN = 60.0;  // the tip force arrow's length per newton (in the screen plane)
constexpr double kForceMaxPx = 90.0;
constexpr int kForceThicknessPx = 2;

dds::Vector3 to_vector(const std::array<float, 3>& p) { return {p[0], p[1], p[2]}; }
dds::Vector3 minus(const dds::Vector3& a, const dds::Vector3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
double dot(const dds::Vector3& a, const dds::Vector3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
dds::Vector3 cross(const dds::Vector3& a, const dds::Vector3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

/// The surface colour lit by a headlight: facing the viewer (either side) is brightest.
cv::Scalar shade(const dds::Vector3& normal, const dds::Vector3& toward_viewer) {
  const double length = std::sqrt(dot(normal, normal));
  const double facing = length > 0.0 ? std::abs(dot(normal, toward_viewer)) / length : 0.0;
  return palette::kSurface * (kAmbientLight + (1.0 - kAmbientLight) * facing);
}

/// The needle's centreline (a dot when only its tip is known) over an arrow, from the tip, of
/// the force on the tip: kForcePxPerN per newton (at most kForceMaxPx), foreshortened by the view.
void draw_needle(cv::Mat& panel, const OrthoCamera& camera, const dds::NeedleState& needle) {
  if (needle.point_count == 0) return;
  const cv::Point2d tip = camera.to_panel(needle.shape_points_m[needle.point_count - 1]);
  const double force_n = std::sqrt(dot(needle.tip_force_n, needle.tip_force_n));
  if (force_n > 0.0) {
    const double px_per_n = std::min(kForcePxPerN * force_n, kForceMaxPx) / force_n;
    const cv::Point2d end =
        tip + px_per_n * cv::Point2d(dot(needle.tip_force_n, camera.right), -dot(needle.tip_force_n, camera.up));
    cv::arrowedLine(panel, to_fixed_point(tip), to_fixed_point(end), palette::kForce, kForceThicknessPx, cv::LINE_AA,
                    kSubpixelBits, 0.3);
  }
  for (std::uint32_t i = 1; i < needle.point_count; ++i)
    draw_segment(panel, camera.to_panel(needle.shape_points_m[i - 1]), camera.to_panel(needle.shape_points_m[i]),
                 palette::kNeedle, kSurfaceNeedleThicknessPx);
  if (needle.point_count == 1) draw_marker(panel, tip, kTipRadiusPx, palette::kNeedle);
}

}  // namespace

OrthoCamera OrthoCamera::from_angles(const dds::Vector3& look_at_m, double azimuth_deg, double elevation_deg,
                                     double panel_px_per_m, int panel_size_px) {
  const double azimuth = azimuth_deg * M_PI / 180.0;
  const double elevation = elevation_deg * M_PI / 180.0;
  OrthoCamera camera;
  camera.look_at_m = look_at_m;
  camera.toward_viewer = {std::cos(elevation) * std::sin(azimuth), std::sin(elevation),
                          std::cos(elevation) * std::cos(azimuth)};
  camera.right = {std::cos(azimuth), 0.0, -std::sin(azimuth)};
  camera.up = cross(camera.toward_viewer, camera.right);
  camera.panel_px_per_m = panel_px_per_m;
  camera.panel_centre_px = 0.5 * (panel_size_px - 1);
  return camera;
}

cv::Point2d OrthoCamera::to_panel(const dds::Vector3& point_m) const {
  const dds::Vector3 offset = minus(point_m, look_at_m);
  return {panel_centre_px + panel_px_per_m * dot(offset, right), panel_centre_px - panel_px_per_m * dot(offset, up)};
}

double OrthoCamera::depth_m(const dds::Vector3& point_m) const { return dot(minus(point_m, look_at_m), toward_viewer); }

OrthoCamera fit_camera(const dds::DeformedSurface& surface, double azimuth_deg, double elevation_deg,
                       int panel_size_px) {
  dds::Vector3 low{0.0, 0.0, 0.0}, high{0.0, 0.0, 0.0};
  for (std::uint32_t i = 0; i < surface.vertex_count; ++i) {
    const dds::Vector3 p = to_vector(surface.vertex_positions_m[i]);
    for (int axis = 0; axis < 3; ++axis) {
      low[axis] = i == 0 ? p[axis] : std::min(low[axis], p[axis]);
      high[axis] = i == 0 ? p[axis] : std::max(high[axis], p[axis]);
    }
  }
  const dds::Vector3 centre{0.5 * (low[0] + high[0]), 0.5 * (low[1] + high[1]), 0.5 * (low[2] + high[2])};
  double radius_m = 0.0;
  for (std::uint32_t i = 0; i < surface.vertex_count; ++i) {
    const dds::Vector3 offset = minus(to_vector(surface.vertex_positions_m[i]), centre);
    radius_m = std::max(radius_m, std::sqrt(dot(offset, offset)));
  }
  const double px_per_m = radius_m > 0.0 ? 0.5 * kFitFraction * panel_size_px / radius_m : 1.0;
  return OrthoCamera::from_angles(centre, azimuth_deg, elevation_deg, px_per_m, panel_size_px);
}

void SurfacePainter::draw_triangles(cv::Mat& panel, const OrthoCamera& camera, const dds::DeformedSurface& surface,
                                    const SurfaceTriangles& triangles) {
  const auto vertex = [&](std::int32_t index) {
    return to_vector(surface.vertex_positions_m[static_cast<std::size_t>(index)]);
  };
  depth_order_.clear();
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    const auto& [a, b, c] = triangles[t];
    const auto count = static_cast<std::int32_t>(surface.vertex_count);
    if (std::max({a, b, c}) >= count || std::min({a, b, c}) < 0) continue;
    depth_order_.emplace_back(camera.depth_m(vertex(a)) + camera.depth_m(vertex(b)) + camera.depth_m(vertex(c)), t);
  }
  std::stable_sort(depth_order_.begin(), depth_order_.end(),
                   [](const auto& left, const auto& right) { return left.first < right.first; });
  for (const auto& [depth, t] : depth_order_) {
    const auto& [a, b, c] = triangles[t];
    const dds::Vector3 normal = cross(minus(vertex(b), vertex(a)), minus(vertex(c), vertex(a)));
    const cv::Point corners[3] = {to_fixed_point(camera.to_panel(vertex(a))),
                                  to_fixed_point(camera.to_panel(vertex(b))),
                                  to_fixed_point(camera.to_panel(vertex(c)))};
    cv::fillConvexPoly(panel, corners, 3, shade(normal, camera.toward_viewer), cv::LINE_8, kSubpixelBits);
  }
}

void SurfacePainter::draw(cv::Mat& panel, const OrthoCamera& camera, const dds::DeformedSurface& surface,
                          const SurfaceTriangles& triangles, const dds::NeedleState* needle,
                          const dds::TargetPrediction* prediction) {
  panel.setTo(palette::kSurfaceBackground);
  if (!triangles.empty()) {
    draw_triangles(panel, camera, surface, triangles);
  } else {
    for (std::uint32_t i = 0; i < surface.vertex_count; ++i) {
      const cv::Point2d p = camera.to_panel(to_vector(surface.vertex_positions_m[i]));
      cv::circle(panel, to_fixed_point(p), 1 << kSubpixelBits, palette::kSurface, cv::FILLED, cv::LINE_8,
                 kSubpixelBits);
    }
  }
  if (needle != nullptr) draw_needle(panel, camera, *needle);
  if (prediction != nullptr)
    draw_marker(panel, camera.to_panel(prediction->position_m), kSurfaceTargetRadiusPx, palette::kTarget);
}

}  // namespace nav::view
