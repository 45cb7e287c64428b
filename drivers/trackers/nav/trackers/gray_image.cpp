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
  if (!file) return Error{"cannot open the image", path, 0, ""};
  std::string magic;
  int width = 0, height = 0, maxval = 0;
  file >> magic;
  if (magic != "P5") return Error{"not a binary PGM (P5)", path, 1, "magic"};
  file >> width >> height >> maxval;
  if (!file || width <= 0 || height <= 0 || width > 16384 || height > 16384) {
    return Error{"bad image size", path, 1, "width/height"};
  }
  if (maxval != 255) return Error{"only 8-bit PGM (maxval 255) is supported", path, 1, "maxval"};
  file.get();  // the single whitespace before the pixels
  GrayImage image{width, height, std::vector<std::uint8_t>(static_cast<std::size_t>(width) * height)};
  file.read(reinterpret_cast<char*>(image.pixels.data()), static_cast<std::streamsize>(image.pixels.size()));
  if (!file) return Error{"image data truncated", path, 0, "pixels"};
  return image;
}

Status write_pgm(const std::string& path, const GrayImage& image) {
  std::ofstream file(path, std::ios::binary);
  file << "P5\n" << image.width_px << " " << image.height_px << "\n255\n";
  file.write(reinterpret_cast<const char*>(image.pixels.data()), static_cast<std::streamsize>(image.pixels.size()));
  if (!file) return Error{"cannot write the image", path, 0, ""};
  return Done{};
}

Result<std::vector<std::string>> list_pgm_files(const std::string& folder) {
  std::error_code error;
  std::vector<std::string> files;
  for (const auto& entry : std::filesystem::directory_iterator(folder, error)) {
    if (entry.is_regular_file() && entry.path().extension() == ".pgm") files.push_back(entry.path().string());
  }
  if (error) return Error{"cannot list the image folder: " + error.message(), folder, 0, ""};
  std::sort(files.begin(), files.end());
  return files;
}

}  // namespace nav::trackers
