#pragma once
// The station's health on the display: a band across the bottom (mode, raised flags, samples
// dropped; green while healthy, red otherwise) and, above it in the 3-D panel, one line per
// input with its state and the age of its newest sample in words.
#include <opencv2/core/mat.hpp>

#include "nav/dds/samples.hpp"

namespace nav::view {

/// Height of the band across the canvas's bottom.
inline constexpr int kStatusBandPx = 22;

/// Draws the band across `canvas`'s bottom.
void draw_status_band(cv::Mat& canvas, const dds::StationHealth& health);

/// Draws one line per input in `panel`'s lower left, above the band: on green while the input is
/// healthy, on red when it has a flag raised, on grey while nothing was received from it.
void draw_input_lines(cv::Mat& panel, const dds::StationHealth& health);

}  // namespace nav::view
