#pragma once
// Finds the N-wire dots in a B-mode frame (OpenCV imgproc): the frame filtered as PLUS's
// fiducial segmentation filters it (elongated structures and specks taken away by morphology),
// bright compact blobs of what is left inside the clip rectangle, each at its centroid weighted
// by the square of the filtered intensity, grouped into collinear triples, one per wire pattern, the triples
// nearly parallel. Defaults follow the fCal 2.0 segmentation parameters of PLUS.
#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include <Eigen/Core>

namespace nav::calibration {

/// Settings of find_nwire_dots (pixels unless named otherwise).
struct NWireSegmentationOptions {
  std::array<int, 4> clip_xywh{27, 27, 766, 562};
  int bar_half_length_px = 26;      ///< MorphologicalOpeningBarSizeMm 2.0 at 0.078 mm a pixel
  int opening_radius_px = 3;        ///< MorphologicalOpeningCircleRadiusMm 0.27 at 0.078 mm a pixel
  double threshold_fraction = 0.1;  ///< of the filtered clip's range above its darkest (ThresholdImagePercent 10)
  double min_dot_area_px = 6.0;
  double max_dot_area_px = 1500.0;
  double max_dot_elongation = 5.0;  ///< bounding box's longer over shorter side
  std::size_t max_candidates = 20;  ///< the brightest blobs kept
  double collinear_tolerance_px = 8.0;
  double min_line_length_px = 100.0;
  double max_line_angle_rad = 1.22;         ///< 70 degrees from the image rows
  double max_angle_difference_rad = 0.175;  ///< 10 degrees between the lines
};

/// Three dots of one pattern, left to right in the image (pixels).
using NWireLine = std::array<Eigen::Vector2d, 3>;

/// The dots of `line_count` patterns, lines ordered top to bottom; nullopt when the frame
/// does not show that many well-formed lines.
std::optional<std::vector<NWireLine>> find_nwire_dots(const std::uint8_t* pixels, int width_px, int height_px,
                                                      std::size_t line_count,
                                                      const NWireSegmentationOptions& options = {});

}  // namespace nav::calibration
