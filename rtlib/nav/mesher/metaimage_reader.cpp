#include "nav/mesher/metaimage_reader.hpp"

#include <algorithm>
#include <array>
#include <filesystem>
#include <optional>
#include <string_view>
#include <vector>

#include "nav/mesh/text_lines.hpp"

namespace nav {
namespace {

constexpr std::int64_t kMaxVoxels = std::int64_t{1} << 31;

std::string_view trim(std::string_view text) {
  const auto first = text.find_first_not_of(" \t\r");
  if (first == std::string_view::npos) return {};
  return text.substr(first, text.find_last_not_of(" \t\r") - first + 1);
}

std::vector<std::string_view> split_words(std::string_view text) {
  std::vector<std::string_view> words;
  std::size_t position = 0;
  while ((position = text.find_first_not_of(" \t", position)) != std::string_view::npos) {
    const auto end = std::min(text.find_first_of(" \t", position), text.size());
    words.push_back(text.substr(position, end - position));
    position = end;
  }
  return words;
}

/// What the header says about the voxels; the line of ElementDataFile, which ends it.
struct Header {
  bool three_dimensional = false;
  std::optional<std::array<std::int64_t, 3>> size;
  Point3 spacing{1.0, 1.0, 1.0};
  Point3 offset{0.0, 0.0, 0.0};
  bool element_type_seen = false;
  std::string data_file;
  int data_file_line = 0;
  std::size_t data_start = 0;  ///< byte after the ElementDataFile line
};

/// Parses the "Key = Value" lines of a MetaImage header up to ElementDataFile.
class HeaderParser {
 public:
  HeaderParser(const std::string& path, const std::string& text) : path_(path), text_(text) {}

  /// Fills `header`, or gives the Error of the first faulty line.
  std::optional<Error> parse(Header& header) {
    std::size_t position = 0;
    int line = 0;
    while (position < text_.size()) {
      ++line;
      const auto end = std::min(text_.find('\n', position), text_.size());
      const std::string_view content = trim(std::string_view(text_).substr(position, end - position));
      position = std::min(end + 1, text_.size());
      if (content.empty()) continue;
      const auto equals = content.find('=');
      if (equals == std::string_view::npos) return error(line, std::string(content), "expected 'Key = Value'");
      const std::string key(trim(content.substr(0, equals)));
      const std::string_view value = trim(content.substr(equals + 1));
      if (auto problem = geometry_field(header, line, key, value)) return problem;
      if (auto problem = format_field(header, line, key, value)) return problem;
      if (key == "ElementDataFile") {
        header.data_start = position;
        return data_file_field(header, line, value);
      }
    }
    return error(line, "ElementDataFile", "missing (the header must end with it)");
  }

 private:
  Error error(int line, std::string field, std::string message) const {
    return Error{.message = std::move(message), .file = path_, .line = line, .field = std::move(field)};
  }

  /// Reads three numbers from `value` with `parse`, each satisfying `valid`.
  template <typename Number, typename Parse, typename Valid>
  std::optional<Error> triple(int line, const std::string& key, std::string_view value, Parse parse, Valid valid,
                              const char* expected, std::array<Number, 3>& out) const {
    const auto words = split_words(value);
    if (words.size() != 3) {
      return error(line, key, "expected 3 values (NDims = 3), found " + std::to_string(words.size()));
    }
    for (std::size_t a = 0; a < 3; ++a) {
      const auto number = parse(words[a]);
      if (!number || !valid(*number)) {
        return error(line, key, "expected " + std::string(expected) + ", found '" + std::string(words[a]) + "'");
      }
      out[a] = *number;
    }
    return std::nullopt;
  }

  /// NDims, DimSize, ElementSpacing and Offset (alias Origin, Position).
  std::optional<Error> geometry_field(Header& header, int line, const std::string& key, std::string_view value) const {
    const auto positive = [](auto v) { return v > 0; };
    const auto any = [](double) { return true; };
    if (key == "NDims") {
      header.three_dimensional = parse_int(value) == 3;
      if (!header.three_dimensional)
        return error(line, key, "only 3-D volumes are supported, found '" + std::string(value) + "'");
    } else if (key == "DimSize") {
      std::array<std::int64_t, 3> size{};
      if (auto problem = triple(line, key, value, parse_int, positive, "a positive integer", size)) return problem;
      const bool too_large = size[0] > kMaxVoxels || size[1] > kMaxVoxels || size[2] > kMaxVoxels ||
                             size[0] * size[1] > kMaxVoxels || size[0] * size[1] * size[2] > kMaxVoxels;
      if (too_large) return error(line, key, "volume too large (more than 2^31 voxels)");
      header.size = size;
    } else if (key == "ElementSpacing") {
      return triple(line, key, value, parse_double, positive, "a positive number", header.spacing);
    } else if (key == "Offset" || key == "Origin" || key == "Position") {
      return triple(line, key, value, parse_double, any, "a number", header.offset);
    }
    return std::nullopt;
  }

  /// The fields that say how the voxels are stored: only uncompressed binary bytes, one
  /// channel, no rotation.
  std::optional<Error> format_field(Header& header, int line, const std::string& key, std::string_view value) const {
    if (key == "ObjectType" && value != "Image")
      return error(line, key, "expected Image, found '" + std::string(value) + "'");
    if (key == "ElementType") {
      if (value != "MET_UCHAR")
        return error(line, key, "unsupported element type '" + std::string(value) + "' (only MET_UCHAR)");
      header.element_type_seen = true;
    }
    if (key == "CompressedData" && value != "False") return error(line, key, "compressed voxel data is not supported");
    if (key == "BinaryData" && value != "True") return error(line, key, "ASCII voxel data is not supported");
    if (key == "ElementNumberOfChannels" && value != "1") return error(line, key, "only one channel is supported");
    if (key == "HeaderSize" && value != "0")
      return error(line, key, "a header to skip in the data file is not supported");
    const bool rotation = key == "TransformMatrix" || key == "Rotation" || key == "Orientation";
    if (rotation && split_words(value) != std::vector<std::string_view>{"1", "0", "0", "0", "1", "0", "0", "0", "1"}) {
      return error(line, key, "only axis-aligned volumes (identity matrix) are supported");
    }
    return std::nullopt;
  }

  /// ElementDataFile, the last line: LOCAL or a file name; the required fields must be known.
  std::optional<Error> data_file_field(Header& header, int line, std::string_view value) const {
    if (!header.three_dimensional) return error(line, "NDims", "missing before ElementDataFile");
    if (!header.size) return error(line, "DimSize", "missing before ElementDataFile");
    if (!header.element_type_seen) return error(line, "ElementType", "missing before ElementDataFile");
    if (value.empty() || value == "LIST" || value.find('%') != std::string_view::npos) {
      return error(line, "ElementDataFile", "expected LOCAL or one data file name, found '" + std::string(value) + "'");
    }
    header.data_file = std::string(value);
    header.data_file_line = line;
    return std::nullopt;
  }

  const std::string& path_;
  const std::string& text_;
};

}  // namespace

Result<LabelVolume> read_metaimage_labels(const std::string& path, LengthUnit unit) {
  const auto text = read_text_file(path);
  if (!text.ok()) return text.error();
  Header header;
  if (auto problem = HeaderParser(path, text.value()).parse(header)) return *problem;

  // The voxels: after the header (LOCAL) or in a file beside the header.
  std::optional<Result<std::string>> separate;
  std::string_view data;
  std::string data_name = path;
  if (header.data_file == "LOCAL") {
    data = std::string_view(text.value()).substr(header.data_start);
  } else {
    data_name = (std::filesystem::path(path).parent_path() / header.data_file).string();
    separate = read_text_file(data_name);
    if (!separate->ok()) {
      return Error{.message = "cannot open data file '" + data_name + "': " + separate->error().message,
                   .file = path,
                   .line = header.data_file_line,
                   .field = "ElementDataFile"};
    }
    data = separate->value();
  }
  const auto& size = *header.size;
  const auto expected = static_cast<std::size_t>(size[0] * size[1] * size[2]);
  if (data.size() != expected) {
    return Error{.message = (data.size() < expected ? "truncated voxel data in '"
                                                    : "unexpected bytes after the voxel data in '") +
                            data_name + "': expected " + std::to_string(expected) + " bytes (DimSize), found " +
                            std::to_string(data.size()),
                 .file = path,
                 .line = header.data_file_line,
                 .field = "ElementDataFile"};
  }
  LabelVolume volume;
  const double metres = metres_per_unit(unit);
  for (int a = 0; a < 3; ++a) {
    volume.size[a] = static_cast<std::int32_t>(size[a]);
    volume.spacing_m[a] = header.spacing[a] * metres;
    volume.origin_m[a] = header.offset[a] * metres;
  }
  volume.labels.assign(data.begin(), data.end());
  return volume;
}

}  // namespace nav
