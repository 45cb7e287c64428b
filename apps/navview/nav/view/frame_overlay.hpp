#pragma once
// The ultrasound panel: the B-mode frame scaled to the panel, with the needle, the predicted
// target and its uncertainty drawn over it.
//
// Convention: the station publishes its geometry (needle points, target, surface) in the model
// frame; the overlays are drawn in the image frame of the current ultrasound frame (x along a
// row, y along a column, i.e. depth, z out of the image plane, metres, origin at the centre of
// pixel (0, 0)), through image_from_model: the inverse of where the tracked probe held the
// frame (the station's chain: probe pose at capture time, times the URDF's probe calibration,
// nav/station/image_placement.hpp). Without it the overlays are not drawn: they cannot be placed.
#include <array>

#include <opencv2/core/mat.hpp>

#include "nav/dds/samples.hpp"

namespace nav::view {

/// The probability mass inside the drawn uncertainty ellipse (of the in-plane marginal).
inline constexpr double kEllipseProbability = 0.95;

/// The rigid map from the model frame to a frame's image frame.
struct ImageFromModel {
  std::array<double, 9> rotation{1, 0, 0, 0, 1, 0, 0, 0, 1};  ///< row-major
  dds::Vector3 translation_m{};

  /// `point_m` (model frame) in the image frame.
  dds::Vector3 apply(const dds::Vector3& point_m) const;
  /// `covariance_m2` (model frame, row-major) in the image frame: R C R^T.
  dds::Covariance3 rotate(const dds::Covariance3& covariance_m2) const;
};

/// Maps image-frame metres of one frame to pixels of a panel showing that frame scaled.
struct FramePanelMapping {
  std::array<double, 2> pixel_spacing_m{};  // of the frame: along a row, along a column
  double panel_px_per_frame_px = 1.0;

  /// The mapping for `frame` shown `panel_height_px` high.
  static FramePanelMapping for_frame(const dds::UltrasoundFrame& frame, int panel_height_px);
  /// The panel pixel (OpenCV convention: integer coordinates at pixel centres) of a point.
  cv::Point2d to_panel(const dds::Vector3& point_m) const;
  /// The panel's width for `frame` (its height is the panel height).
  int panel_width_px(const dds::UltrasoundFrame& frame) const;
};

/// An ellipse in panel pixels: centre, half axes and the rotation of the first axis.
struct PanelEllipse {
  cv::Point2d centre_px;
  double half_axis_major_px = 0.0;
  double half_axis_minor_px = 0.0;
  double major_axis_angle_deg = 0.0;  // from the panel's x axis towards its y axis
};

/// The kEllipseProbability ellipse of the in-plane (x, y) part of `prediction`'s covariance,
/// taken into the image frame.
PanelEllipse uncertainty_ellipse(const FramePanelMapping& mapping, const dds::TargetPrediction& prediction,
                                 const ImageFromModel& image_from_model = {});

/// Draws `frame` into `panel` (which must be CV_8UC3, panel-sized) with the overlays that
/// are present (null pointers are left out), placed by `image_from_model` (none: no overlay).
void draw_frame_panel(cv::Mat& panel, const dds::UltrasoundFrame& frame, const dds::NeedleState* needle,
                      const dds::TargetPrediction* prediction, const ImageFromModel* image_from_model);

}  // namespace nav::view
