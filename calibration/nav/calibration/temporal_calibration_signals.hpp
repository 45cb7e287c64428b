#pragma once
// The two signals of a water-tank temporal calibration: the depth of the tank bottom's
// bright line in each frame, and the tracked probe's position along its main direction
// of motion.
#include <array>
#include <cstdint>
#include <limits>
#include <optional>
#include <vector>

#include <Eigen/Core>

#include "nav/calibration/temporal_calibration.hpp"

namespace nav::calibration {

/// The row (pixels) at the clip's centre column of the brightest straight line in an 8-bit
/// frame: per column the intensity-weighted row of the pixels above `threshold_fraction`
/// of the brightest, then a weighted line fit. Nullopt when fewer than `min_columns` columns
/// show the line.
std::optional<double> bright_line_row_px(const std::uint8_t* pixels, int width_px, int height_px,
                                         const std::array<int, 4>& clip_xywh, double threshold_fraction = 0.3,
                                         int min_columns = 20);

/// The positions stamped within [from_s, to_s] projected on their principal direction (largest
/// variance), centred: one value per time. Positions in any consistent unit. A temporal
/// calibration takes the other device's span (shrunk by the search window, as PLUS does), so
/// that motions of the tool before and after the recording do not tilt the direction.
TimedSignal principal_motion(const std::vector<double>& times_s, const std::vector<Eigen::Vector3d>& positions,
                             double from_s = -std::numeric_limits<double>::infinity(),
                             double to_s = std::numeric_limits<double>::infinity());

}  // namespace nav::calibration
