#pragma once
// The two signals of a water-tank temporal calibration: the depth of the tank bottom's
// bright line in each frame, and the tracked probe's position along its main direction
// of motion.
#include <array>
#include <cstdint>
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

/// Positions projected on their principal direction (largest variance), centred: one value
/// per time. Positions in any consistent unit.
TimedSignal principal_motion(const std::vector<double>& times_s, const std::vector<Eigen::Vector3d>& positions);

}  // namespace nav::calibration
