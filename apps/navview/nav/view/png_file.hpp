#pragma once
// PNG files of 8-bit images, written with zlib alone (OpenCV's imgcodecs is not a
// dependency): colour type 2 (RGB) or 0 (gray), no interlace, filter type 0 on every row.
// The reader reads exactly that subset back, so tests can look at what navview wrote.
#include <string>

#include <opencv2/core/mat.hpp>

#include "nav/core/error.hpp"

namespace nav::view {

/// Writes `image` (CV_8UC3 in OpenCV's BGR order, or CV_8UC1) as a PNG file at `path`.
/// The file appears whole or not at all: it is written next to `path` and then renamed.
Status write_png(const std::string& path, const cv::Mat& image);

/// Reads a PNG of the subset write_png writes: CV_8UC3 (BGR) or CV_8UC1. Checks every
/// chunk's CRC; anything else (other depths, palettes, interlace, filters) is an Error.
Result<cv::Mat> read_png(const std::string& path);

}  // namespace nav::view
