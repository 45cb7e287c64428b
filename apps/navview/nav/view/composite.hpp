#pragma once
// navview's picture: the ultrasound panel (frame, needle, target, uncertainty) on the left
// and the 3-D panel (deformed surface, needle, target) on the right, each with a caption, and
// the station's health (health_panel.hpp).
// Pure drawing from plain samples: no DDS, no window, so tests can check its pixels.
#include <string>

#include <opencv2/core/mat.hpp>

#include "nav/dds/samples.hpp"
#include "nav/view/surface_view.hpp"
#include "nav/view/view_control.hpp"

namespace nav::view {

struct ImageFromModel;  // frame_overlay.hpp

/// The newest sample of each stream the display shows; null when none arrived yet.
struct DisplayInputs {
  const dds::UltrasoundFrame* frame = nullptr;
  const dds::NeedleState* needle = nullptr;
  const dds::TargetPrediction* prediction = nullptr;
  const dds::DeformedSurface* surface = nullptr;
  /// Where the frame lies (the inverse of its placement); null while it cannot be placed, and
  /// then the frame is drawn without overlays.
  const ImageFromModel* image_from_model = nullptr;
};

/// The composite's size and the 3-D panel's viewing angles.
struct CompositeOptions {
  int panel_height_px = 512;  // both panels; the 3-D panel is square
  double view_azimuth_deg = 30.0;
  double view_elevation_deg = 20.0;
  bool captions = true;      // one line of figures at the top of each panel
  bool interactive = false;  // in a window: "h: help" in the 3-D panel's corner
};

/// Renders composites into one canvas it keeps. The 3-D camera is fitted to the first
/// surface drawn and then kept, so that deformation shows as motion, not as re-framing; view()
/// orbits and zooms it.
class Composer {
 public:
  Composer(const CompositeOptions& options, SurfaceTriangles surface_triangles);

  /// The composite of `inputs` (valid until the next call). Its width is the frame panel's
  /// (the frame scaled to panel_height_px, or a square while no frame arrived) plus the
  /// 3-D panel's. With a `status`, a band across its bottom gives the station's mode, raised
  /// flags and dropped samples: green while it runs healthy, red otherwise; above it, in the
  /// 3-D panel, each input's state and age.
  const cv::Mat& render(const DisplayInputs& inputs, const dds::StationHealth* health = nullptr);

  /// The 3-D panel's view, which the next render uses.
  ViewControl& view() { return view_; }

 private:
  CompositeOptions options_;
  SurfaceTriangles surface_triangles_;
  SurfacePainter painter_;
  ViewControl view_;
  OrthoCamera fitted_camera_;  // the first surface's, at zoom 1
  bool camera_fitted_ = false;
  cv::Mat canvas_;
};

}  // namespace nav::view
