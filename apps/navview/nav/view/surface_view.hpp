#pragma once
// The 3-D panel: the deformed organ surface, flat-shaded and drawn back to front (painter's
// algorithm) through an orthographic camera, with the needle (shape and tip force) and the
// target on top.
#include <array>
#include <cstdint>
#include <utility>
#include <vector>

#include <opencv2/core/mat.hpp>

#include "nav/dds/samples.hpp"

namespace nav::view {

/// The triangles of a surface, as vertex indices into DeformedSurface::vertex_positions_m.
using SurfaceTriangles = std::vector<std::array<std::int32_t, 3>>;

/// An orthographic camera onto a square panel. The display frame's points project along
/// `toward_viewer_m`; `right` and `up` span the screen (y of the panel grows downwards).
struct OrthoCamera {
  dds::Vector3 look_at_m{};
  dds::Vector3 right{1.0, 0.0, 0.0};
  dds::Vector3 up{0.0, 1.0, 0.0};
  dds::Vector3 toward_viewer{0.0, 0.0, 1.0};
  double panel_px_per_m = 1.0;
  double panel_centre_px = 0.0;

  /// A camera looking at `look_at_m` from azimuth (about the up axis y, 0 looking down -z)
  /// and elevation (above the x-z plane), for a panel of `panel_size_px` square.
  static OrthoCamera from_angles(const dds::Vector3& look_at_m, double azimuth_deg, double elevation_deg,
                                 double panel_px_per_m, int panel_size_px);
  /// The panel pixel of `point_m`.
  cv::Point2d to_panel(const dds::Vector3& point_m) const;
  /// How far `point_m` is in front of the look-at point, towards the viewer (metres).
  double depth_m(const dds::Vector3& point_m) const;
};

/// A camera at the given angles that frames `surface`'s vertices in a panel of
/// `panel_size_px` (its bounding sphere spans 90 % of the panel).
OrthoCamera fit_camera(const dds::DeformedSurface& surface, double azimuth_deg, double elevation_deg,
                       int panel_size_px);

/// Draws surfaces into the 3-D panel; keeps its sorting scratch between frames.
class SurfacePainter {
 public:
  /// Clears `panel` and draws `surface` (its triangles; its vertices as dots when there are
  /// none), then the needle (its shape, or its tip alone, with an arrow of the tip force) and
  /// the target if present. Triangles naming a vertex beyond the
  /// surface's vertex_count are left out.
  void draw(cv::Mat& panel, const OrthoCamera& camera, const dds::DeformedSurface& surface,
            const SurfaceTriangles& triangles, const dds::NeedleState* needle, const dds::TargetPrediction* prediction);

 private:
  void draw_triangles(cv::Mat& panel, const OrthoCamera& camera, const dds::DeformedSurface& surface,
                      const SurfaceTriangles& triangles);

  std::vector<std::pair<double, std::size_t>> depth_order_;  // (depth, triangle), far first
};

}  // namespace nav::view
