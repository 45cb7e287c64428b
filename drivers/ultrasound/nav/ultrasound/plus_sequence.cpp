#include "nav/ultrasound/plus_sequence.hpp"

#include <zlib.h>

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fstream>
#include <iterator>
#include <optional>
#include <sstream>

namespace nav::ultrasound {
namespace {

constexpr std::size_t kMaxFrames = 100000;
constexpr std::uint32_t kMaxSidePx = 16384;
constexpr std::size_t kMaxPixelBytes = std::size_t{1} << 31;
constexpr std::size_t kMaxDeflateRatio = 1032;
constexpr double kNoTimestamp = std::numeric_limits<double>::quiet_NaN();

std::string_view trim(std::string_view text) {
  const auto first = text.find_first_not_of(" \t\r");
  if (first == std::string_view::npos) return {};
  return text.substr(first, text.find_last_not_of(" \t\r") - first + 1);
}

bool ends_with(std::string_view text, std::string_view suffix) {
  return text.size() >= suffix.size() && text.substr(text.size() - suffix.size()) == suffix;
}

/// Whitespace-separated numbers; nullopt if any word is not one, or if they are not `count`
/// (count 0: any number of them).
std::optional<std::vector<double>> parse_numbers(std::string_view text, std::size_t count) {
  std::vector<double> numbers;
  std::size_t position = 0;
  while ((position = text.find_first_not_of(" \t", position)) != std::string_view::npos) {
    const auto end = std::min(text.find_first_of(" \t", position), text.size());
    double value = 0.0;
    const auto [last, error] = std::from_chars(text.data() + position, text.data() + end, value);
    if (error != std::errc{} || last != text.data() + end || !std::isfinite(value)) return std::nullopt;
    numbers.push_back(value);
    position = end;
  }
  if (count != 0 && numbers.size() != count) return std::nullopt;
  return numbers;
}

/// Builds the sequence from the header lines, one "key, value" at a time.
class HeaderReader {
 public:
  HeaderReader(const std::string& name, PlusSequence& sequence) : name_(name), sequence_(sequence) {}

  Error error(int line, std::string field, std::string message) const {
    return Error{.message = std::move(message), .file = name_, .line = line, .field = std::move(field)};
  }

  /// MetaImage and NRRD geometry fields, normalised by the caller to these keys.
  std::optional<Error> field(int line, const std::string& key, std::string_view value) {
    if (key == "DimSize" || key == "sizes") return sizes(line, key, value);
    if (key == "NDims" || key == "dimension") {
      if (value != "3") return error(line, key, "only 3-D sequences (frames x count) are supported");
    } else if (key == "ElementType" || key == "type") {
      element_type_ok_ = value == "MET_UCHAR" || value == "uint8" || value == "uchar" || value == "unsigned char";
      element_type_line_ = line;
    } else if (key == "CompressedData") {
      compressed_ = value == "True";
    } else if (key == "encoding") {
      if (value != "raw" && value != "gz" && value != "gzip")
        return error(line, key, "unsupported encoding '" + std::string(value) + "'");
      compressed_ = value != "raw";
    } else if (key == "ElementSpacing") {
      const auto numbers = parse_numbers(value, 3);
      if (!numbers || (*numbers)[0] <= 0.0 || (*numbers)[1] <= 0.0)
        return error(line, key, "expected three positive numbers");
      sequence_.spacing_mm = {(*numbers)[0], (*numbers)[1]};
    } else if (key == "UltrasoundImageOrientation" || key == "ultrasound image orientation") {
      sequence_.image_orientation = std::string(value);
    } else if (key.rfind("Seq_Frame", 0) == 0) {
      return frame_field(line, key, value);
    }
    return std::nullopt;
  }

  /// Checks what the whole header must have said.
  std::optional<Error> finish(int last_line) const {
    if (!sizes_seen_) return error(last_line, "DimSize", "missing");
    if (sequence_.frame_pixels() > 0 && !element_type_ok_) {
      return error(element_type_line_, "ElementType", "frames must be 8-bit unsigned (MET_UCHAR / uint8)");
    }
    for (std::size_t i = 0; i < sequence_.frame_count; ++i) {
      if (std::isnan(sequence_.timestamps_s[i])) return error(last_line, frame_key(i, "Timestamp"), "missing");
    }
    return std::nullopt;
  }

  bool compressed() const noexcept { return compressed_; }

 private:
  static std::string frame_key(std::size_t index, const char* what) {
    std::ostringstream key;
    key << "Seq_Frame" << index << '_' << what;
    return key.str();
  }

  std::optional<Error> sizes(int line, const std::string& key, std::string_view value) {
    const auto numbers = parse_numbers(value, 3);
    if (!numbers) return error(line, key, "expected three sizes");
    for (const double size : *numbers) {
      if (size < 0.0 || size != std::floor(size)) return error(line, key, "sizes must be whole and not negative");
    }
    if ((*numbers)[0] > kMaxSidePx || (*numbers)[1] > kMaxSidePx || (*numbers)[2] > static_cast<double>(kMaxFrames)) {
      return error(line, key, "sizes too large");
    }
    if (sizes_seen_) return error(line, key, "given twice");
    sizes_seen_ = true;
    sequence_.width_px = static_cast<std::uint32_t>((*numbers)[0]);
    sequence_.height_px = static_cast<std::uint32_t>((*numbers)[1]);
    sequence_.frame_count = static_cast<std::size_t>((*numbers)[2]);
    sequence_.timestamps_s.assign(sequence_.frame_count, kNoTimestamp);
    sequence_.image_valid.assign(sequence_.frame_count, 1);
    return std::nullopt;
  }

  /// Seq_FrameNNNN_<what> = value.
  std::optional<Error> frame_field(int line, const std::string& key, std::string_view value) {
    const std::string_view rest = std::string_view(key).substr(9);
    const auto underscore = rest.find('_');
    std::size_t index = 0;
    const auto [last, problem] = std::from_chars(rest.data(), rest.data() + std::min(underscore, rest.size()), index);
    if (underscore == std::string_view::npos || problem != std::errc{} || last != rest.data() + underscore) {
      return error(line, key, "expected Seq_Frame<number>_<field>");
    }
    if (!sizes_seen_) return error(line, key, "frame fields must follow DimSize");
    if (index >= sequence_.frame_count) return error(line, key, "frame index beyond the frame count");
    const std::string_view what = rest.substr(underscore + 1);
    if (what == "Timestamp") {
      const auto numbers = parse_numbers(value, 1);
      if (!numbers) return error(line, key, "expected a time in seconds");
      sequence_.timestamps_s[index] = (*numbers)[0];
    } else if (what == "ImageStatus" || what == "Status") {
      sequence_.image_valid[index] = value == "OK" ? 1 : 0;
    } else if (ends_with(what, "TransformStatus")) {
      track(what.substr(0, what.size() - 15)).valid[index] |= value == "OK" ? 0 : 2;
    } else if (ends_with(what, "Transform")) {
      const auto numbers = parse_numbers(value, 16);
      if (!numbers) return error(line, key, "expected 16 numbers (a row-major 4x4 matrix)");
      TransformTrack& transforms = track(what.substr(0, what.size() - 9));
      std::copy(numbers->begin(), numbers->end(), transforms.matrices_mm[index].begin());
      transforms.valid[index] |= 1;
    }
    return std::nullopt;
  }

  TransformTrack& track(std::string_view name) {
    for (TransformTrack& existing : sequence_.transforms) {
      if (existing.name == name) return existing;
    }
    TransformTrack& added = sequence_.transforms.emplace_back();
    added.name = std::string(name);
    added.matrices_mm.assign(sequence_.frame_count, Matrix4Mm{1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1});
    added.valid.assign(sequence_.frame_count, 0);
    return added;
  }

  const std::string& name_;
  PlusSequence& sequence_;
  bool sizes_seen_ = false;
  bool element_type_ok_ = false;
  int element_type_line_ = 0;
  bool compressed_ = false;
};

/// Normalises one header line into (key, value); the MetaImage "=" or the NRRD ":" / ":=".
bool split_line(std::string_view content, bool nrrd, std::string& key, std::string_view& value) {
  const auto separator = content.find(nrrd ? ':' : '=');
  if (separator == std::string_view::npos) return false;
  key = std::string(trim(content.substr(0, separator)));
  std::size_t value_start = separator + 1;
  if (nrrd && value_start < content.size() && content[value_start] == '=') ++value_start;
  value = trim(content.substr(value_start));
  return true;
}

/// Reads the header; on success gives the offset of the first pixel byte.
Result<std::size_t> read_header(std::string_view bytes, bool nrrd, HeaderReader& reader) {
  std::size_t position = 0;
  int line = 0;
  if (nrrd) {
    const auto end = std::min(bytes.find('\n'), bytes.size());
    if (bytes.substr(0, 4) != "NRRD") return reader.error(1, "magic", "not an NRRD file (no NRRD000x line)");
    position = std::min(end + 1, bytes.size());
    line = 1;
  }
  while (position < bytes.size()) {
    ++line;
    const auto end = std::min(bytes.find('\n', position), bytes.size());
    const std::string_view content = trim(bytes.substr(position, end - position));
    position = std::min(end + 1, bytes.size());
    if (nrrd && content.empty()) {
      if (auto problem = reader.finish(line)) return *problem;
      return position;
    }
    if (content.empty() || content.front() == '#') continue;
    std::string key;
    std::string_view value;
    if (!split_line(content, nrrd, key, value)) {
      return reader.error(line, std::string(content.substr(0, 40)),
                          nrrd ? "expected 'key: value' or 'key:=value'" : "expected 'Key = Value'");
    }
    if (auto problem = reader.field(line, key, value)) return *problem;
    if (!nrrd && key == "ElementDataFile") {
      if (value != "LOCAL") return reader.error(line, key, "only LOCAL data (pixels after the header) is supported");
      if (auto problem = reader.finish(line)) return *problem;
      return position;
    }
  }
  return reader.error(line, nrrd ? "header" : "ElementDataFile", "missing (the header has no end)");
}

/// Inflates zlib or gzip data until `out` is full; false if the stream is bad or too short.
bool inflate_into(std::string_view compressed, std::vector<std::uint8_t>& out) {
  z_stream stream{};
  if (inflateInit2(&stream, 15 + 32) != Z_OK) return false;
  stream.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(compressed.data()));
  stream.avail_in = static_cast<uInt>(std::min<std::size_t>(compressed.size(), std::numeric_limits<uInt>::max()));
  std::size_t produced = 0;
  int status = Z_OK;
  while (produced < out.size() && status == Z_OK) {
    stream.next_out = out.data() + produced;
    stream.avail_out = static_cast<uInt>(std::min<std::size_t>(out.size() - produced, std::size_t{1} << 30));
    const uInt before = stream.avail_out;
    status = inflate(&stream, Z_NO_FLUSH);
    produced += before - stream.avail_out;
    if (status == Z_BUF_ERROR && stream.avail_in == 0) break;
    if (status == Z_BUF_ERROR) status = Z_OK;
  }
  inflateEnd(&stream);
  return produced == out.size();
}

}  // namespace

const TransformTrack* PlusSequence::find_transform(std::string_view name) const noexcept {
  for (const TransformTrack& track : transforms) {
    if (track.name == name) return &track;
  }
  return nullptr;
}

Result<PlusSequence> parse_plus_sequence(std::string_view bytes, const std::string& name,
                                         const PlusReadOptions& options) {
  PlusSequence sequence;
  sequence.path = name;
  const bool nrrd = ends_with(name, ".nrrd");
  HeaderReader reader(name, sequence);
  auto data_start = read_header(bytes, nrrd, reader);
  if (!data_start) return data_start.error();
  for (TransformTrack& track : sequence.transforms) {
    for (std::uint8_t& valid : track.valid) valid = valid == 1 ? 1 : 0;
  }
  const std::size_t frames = std::min(options.max_frames, sequence.frame_count);
  if (sequence.frame_pixels() == 0 || frames == 0) return sequence;
  const std::size_t wanted = sequence.frame_pixels() * frames;
  if (wanted > kMaxPixelBytes) return reader.error(0, "pixels", "too many pixels to read at once");
  // Checked before allocating: raw data must hold the frames, and deflate expands at most
  // about 1032 times.
  const std::string_view data = bytes.substr(data_start.value());
  if (data.size() < (reader.compressed() ? wanted / kMaxDeflateRatio : wanted)) {
    return reader.error(0, "pixel data", "shorter than the frames the header declares");
  }
  sequence.pixels.resize(wanted);
  if (reader.compressed()) {
    if (!inflate_into(data, sequence.pixels))
      return reader.error(0, "pixel data", "compressed data is corrupt or shorter than the frames");
  } else {
    std::copy_n(data.begin(), wanted, sequence.pixels.begin());
  }
  sequence.frames_read = frames;
  return sequence;
}

Result<PlusSequence> read_plus_sequence(const std::string& path, const PlusReadOptions& options) {
  std::ifstream file(path, std::ios::binary);
  if (!file) return Error{.message = "cannot open", .file = path};
  const std::string bytes((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
  return parse_plus_sequence(bytes, path, options);
}

}  // namespace nav::ultrasound
