#include "nav/view/png_file.hpp"

#include <zlib.h>

#include <array>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <vector>

namespace nav::view {
namespace {

constexpr std::array<std::uint8_t, 8> kSignature = {0x89, 'P', 'N', 'G', '\r', '\n', 0x1a, '\n'};
constexpr std::uint8_t kColourGray = 0;
constexpr std::uint8_t kColourRgb = 2;
constexpr std::uint8_t kFilterNone = 0;
constexpr int kCompressionLevel = 1;  // fastest: navview writes images while it runs

void put_u32(std::vector<std::uint8_t>& out, std::uint32_t value) {
  for (int shift = 24; shift >= 0; shift -= 8) out.push_back(static_cast<std::uint8_t>(value >> shift));
}

std::uint32_t get_u32(const std::uint8_t* bytes) {
  return (std::uint32_t{bytes[0]} << 24) | (std::uint32_t{bytes[1]} << 16) | (std::uint32_t{bytes[2]} << 8) | bytes[3];
}

/// Appends one chunk: length, type, data, CRC-32 of type and data.
void put_chunk(std::vector<std::uint8_t>& out, const char (&type)[5], const std::vector<std::uint8_t>& data) {
  put_u32(out, static_cast<std::uint32_t>(data.size()));
  const std::size_t type_at = out.size();
  out.insert(out.end(), type, type + 4);
  out.insert(out.end(), data.begin(), data.end());
  const uLong crc = crc32(0L, out.data() + type_at, static_cast<uInt>(4 + data.size()));
  put_u32(out, static_cast<std::uint32_t>(crc));
}

/// The rows of `image` in PNG order (RGB, not BGR), each led by its filter byte.
std::vector<std::uint8_t> filtered_rows(const cv::Mat& image) {
  const int channels = image.channels();
  std::vector<std::uint8_t> rows;
  rows.reserve(static_cast<std::size_t>(image.rows) * (1 + static_cast<std::size_t>(image.cols) * channels));
  for (int y = 0; y < image.rows; ++y) {
    rows.push_back(kFilterNone);
    const std::uint8_t* row = image.ptr<std::uint8_t>(y);
    for (int x = 0; x < image.cols; ++x, row += channels) {
      if (channels == 3) {
        rows.insert(rows.end(), {row[2], row[1], row[0]});
      } else {
        rows.push_back(row[0]);
      }
    }
  }
  return rows;
}

Error png_error(const std::string& path, const std::string& message) { return Error{.message = message, .file = path}; }

}  // namespace

Status write_png(const std::string& path, const cv::Mat& image) {
  if (image.depth() != CV_8U || (image.channels() != 3 && image.channels() != 1) || image.empty()) {
    return png_error(path, "write_png takes a non-empty 8-bit BGR or gray image");
  }
  std::vector<std::uint8_t> header;
  put_u32(header, static_cast<std::uint32_t>(image.cols));
  put_u32(header, static_cast<std::uint32_t>(image.rows));
  header.insert(header.end(), {8, image.channels() == 3 ? kColourRgb : kColourGray, 0, 0, 0});

  const std::vector<std::uint8_t> rows = filtered_rows(image);
  uLongf compressed_bytes = compressBound(static_cast<uLong>(rows.size()));
  std::vector<std::uint8_t> compressed(compressed_bytes);
  if (compress2(compressed.data(), &compressed_bytes, rows.data(), static_cast<uLong>(rows.size()),
                kCompressionLevel) != Z_OK) {
    return png_error(path, "zlib could not compress the image");
  }
  compressed.resize(compressed_bytes);

  std::vector<std::uint8_t> file(kSignature.begin(), kSignature.end());
  put_chunk(file, "IHDR", header);
  put_chunk(file, "IDAT", compressed);
  put_chunk(file, "IEND", {});

  const std::string partial_path = path + ".partial";
  {
    std::ofstream out(partial_path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(file.data()), static_cast<std::streamsize>(file.size()));
    if (!out) return png_error(partial_path, "cannot write the image file");
  }
  if (std::rename(partial_path.c_str(), path.c_str()) != 0)
    return png_error(path, "cannot rename the finished image into place");
  return Done{};
}

Result<cv::Mat> read_png(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return png_error(path, "cannot open the image file");
  const std::vector<std::uint8_t> file{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  if (file.size() < kSignature.size() || !std::equal(kSignature.begin(), kSignature.end(), file.begin())) {
    return png_error(path, "not a PNG file");
  }
  std::uint32_t width = 0, height = 0;
  std::uint8_t colour = 0;
  std::vector<std::uint8_t> compressed;
  bool ended = false;
  for (std::size_t at = kSignature.size(); !ended;) {
    if (at + 12 > file.size()) return png_error(path, "truncated chunk at byte offset " + std::to_string(at));
    const std::uint32_t length = get_u32(&file[at]);
    if (length > file.size() - at - 12) return png_error(path, "truncated chunk at byte offset " + std::to_string(at));
    const std::uint8_t* type = &file[at + 4];
    const std::uint8_t* data = type + 4;
    if (crc32(0L, type, length + 4) != get_u32(data + length)) {
      return png_error(path, "chunk CRC mismatch at byte offset " + std::to_string(at));
    }
    const std::string name(type, type + 4);
    if (name == "IHDR" && length == 13) {
      width = get_u32(data);
      height = get_u32(data + 4);
      colour = data[9];
      if (data[8] != 8 || (colour != kColourRgb && colour != kColourGray) || data[10] != 0 || data[11] != 0 ||
          data[12] != 0) {
        return png_error(path, "only 8-bit RGB or gray, non-interlaced PNGs are read");
      }
    } else if (name == "IDAT") {
      compressed.insert(compressed.end(), data, data + length);
    } else if (name == "IEND") {
      ended = true;
    }
    at += 12 + length;
  }
  if (width == 0 || height == 0) return png_error(path, "no image header");
  const int channels = colour == kColourRgb ? 3 : 1;
  const std::size_t row_bytes = 1 + std::size_t{width} * channels;
  std::vector<std::uint8_t> rows(row_bytes * height);
  uLongf rows_size = static_cast<uLongf>(rows.size());
  if (uncompress(rows.data(), &rows_size, compressed.data(), static_cast<uLong>(compressed.size())) != Z_OK ||
      rows_size != rows.size()) {
    return png_error(path, "the image data does not decompress to the announced size");
  }
  cv::Mat image(static_cast<int>(height), static_cast<int>(width), channels == 3 ? CV_8UC3 : CV_8UC1);
  for (int y = 0; y < image.rows; ++y) {
    const std::uint8_t* row = &rows[static_cast<std::size_t>(y) * row_bytes];
    if (row[0] != kFilterNone)
      return png_error(path, "row " + std::to_string(y) + " uses a PNG filter this reader does not undo");
    std::uint8_t* out = image.ptr<std::uint8_t>(y);
    for (std::size_t x = 0; x < width; ++x) {
      if (channels == 3) {
        out[3 * x] = row[1 + 3 * x + 2];
        out[3 * x + 1] = row[1 + 3 * x + 1];
        out[3 * x + 2] = row[1 + 3 * x];
      } else {
        out[x] = row[1 + x];
      }
    }
  }
  return image;
}

}  // namespace nav::view
