#pragma once
// Finds the N-wire dots in a B-mode frame (OpenCV imgproc): bright compact blobs inside the
// clip rectangle, grouped into collinear triples, one per wire pattern, the triples nearly
// parallel. Defaults follow the fCal 2.0 segmentation parameters of PLUS.
#include <array>
#include <cstdint>
#include <optional>
#include <vector>

#include <Eigen/Core>

namespace nav::calibration {

/// Settings of find_nwire_dots (pixels unless named otherwise).
struct NWireSegmentationOptions {
  std::array<int, 4> clip_xywh{27, 27, 766, 562};
  double threshold_fraction = 0.2;  ///< of the brightest smoothed pixel in the clip
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
