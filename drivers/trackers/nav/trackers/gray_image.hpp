#pragma once
// 8-bit grey images for the optical tracker: a plain owning buffer, and the image folder
// source (binary PGM files, read in name order) that stands in for a camera.
#include <cstdint>
#include <string>
#include <vector>

#include "nav/core/error.hpp"

namespace nav::trackers {

/// A row-major 8-bit image, width_px * height_px bytes.
struct GrayImage {
  int width_px = 0;
  int height_px = 0;
  std::vector<std::uint8_t> pixels;
};

/// Reads a binary (P5, maxval 255) PGM file; errors name the file and the header field.
Result<GrayImage> read_pgm(const std::string& path);
/// Writes a binary PGM file.
Status write_pgm(const std::string& path, const GrayImage& image);
/// The *.pgm files of `folder`, sorted by name (the frame order of an image folder source).
Result<std::vector<std::string>> list_pgm_files(const std::string& folder);

}  // namespace nav::trackers
