#pragma once
// 8-bit grey images for the optical tracker: a plain owning buffer, the image folder source
// (binary PGM files, read in name order), and the frames of an OpenCV capture (a camera, a
// video or an image sequence through nav::ultrasound::CaptureSource) taken as images.
#include <cstdint>
#include <string>
#include <vector>

#include "nav/core/error.hpp"
#include "nav/dds/samples.hpp"

namespace nav::trackers {

/// A row-major 8-bit image, width_px * height_px bytes.
struct GrayImage {
  int width_px = 0;
  int height_px = 0;
  std::vector<std::uint8_t> pixels;
};

/// The grey pixels of a grabbed frame (as CaptureSource delivers a camera's frames).
GrayImage gray_image_from_frame(const dds::UltrasoundFrame& frame);

/// Reads a binary (P5, maxval 255) PGM file; errors name the file and the header field.
Result<GrayImage> read_pgm(const std::string& path);
/// Writes a binary PGM file.
Status write_pgm(const std::string& path, const GrayImage& image);
/// The *.pgm files of `folder`, sorted by name (the frame order of an image folder source).
Result<std::vector<std::string>> list_pgm_files(const std::string& folder);

}  // namespace nav::trackers
