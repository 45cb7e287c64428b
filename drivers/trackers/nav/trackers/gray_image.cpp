#include "nav/trackers/gray_image.hpp"

#include <algorithm>
#include <filesystem>
#include <fstream>

namespace nav::trackers {

GrayImage gray_image_from_frame(const dds::UltrasoundFrame& frame) {
  GrayImage image{static_cast<int>(frame.width_px), static_cast<int>(frame.height_px), {}};
  image.pixels.assign(frame.pixels.begin(), frame.pixels.begin() + static_cast<std::ptrdiff_t>(frame.pixel_count()));
  return image;
}

Result<GrayImage> read_pgm(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) return Error{.message = "cannot open the image", .file = path};
  std::string magic;
  int width = 0, height = 0, maxval = 0;
  file >> magic;
  if (magic != "P5") return Error{.message = "not a binary PGM (P5)", .file = path, .line = 1, .field = "magic"};
  file >> width >> height >> maxval;
  if (!file || width <= 0 || height <= 0 || width > 16384 || height > 16384) {
    return Error{.message = "bad image size", .file = path, .line = 1, .field = "width/height"};
  }
  if (maxval != 255)
    return Error{.message = "only 8-bit PGM (maxval 255) is supported", .file = path, .line = 1, .field = "maxval"};
  file.get();  // the single whitespace before the pixels
  GrayImage image{width, height, std::vector<std::uint8_t>(static_cast<std::size_t>(width) * height)};
  file.read(reinterpret_cast<char*>(image.pixels.data()), static_cast<std::streamsize>(image.pixels.size()));
  if (!file) return Error{.message = "image data truncated", .file = path, .field = "pixels"};
  return image;
}

Status write_pgm(const std::string& path, const GrayImage& image) {
  std::ofstream file(path, std::ios::binary);
  file << "P5\n" << image.width_px << " " << image.height_px << "\n255\n";
  file.write(reinterpret_cast<const char*>(image.pixels.data()), static_cast<std::streamsize>(image.pixels.size()));
  if (!file) return Error{.message = "cannot write the image", .file = path};
  return Done{};
}

Result<std::vector<std::string>> list_pgm_files(const std::string& folder) {
  std::error_code error;
  std::vector<std::string> files;
  for (const auto& entry : std::filesystem::directory_iterator(folder, error)) {
    if (entry.is_regular_file() && entry.path().extension() == ".pgm") files.push_back(entry.path().string());
  }
  if (error) return Error{.message = "cannot list the image folder: " + error.message(), .file = folder};
  std::sort(files.begin(), files.end());
  return files;
}

}  // namespace nav::trackers
