#include "nav/igtl/igtl_wire.hpp"

#include <igtl_header.h>
#include <igtl_image.h>
#include <igtl_tdata.h>
#include <igtl_transform.h>
#include <igtl_util.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <optional>
#include <string>
#include <utility>

namespace nav::igtl {
namespace {

constexpr std::uint64_t kTransformBodyBytes = 12 * sizeof(float);
constexpr std::uint64_t kImageHeaderBytes = 72;
constexpr std::uint64_t kOtherBodyLimitBytes = std::uint64_t{64} << 10;
constexpr double kLargestTranslationMm = 10'000.0;
constexpr std::size_t kMetadataEntryBytes = 8;  // a v3 metadata header's entry: key size, encoding, value size

/// The big-endian unsigned integer of `count` bytes at `at`.
std::uint64_t big_endian(const std::uint8_t* at, int count) {
  std::uint64_t value = 0;
  for (int i = 0; i < count; ++i) value = (value << 8) | at[i];
  return value;
}

/// The text of a fixed-size, NUL-padded name field, or nullopt when it holds a byte that is
/// not printable ASCII (before its first NUL).
std::optional<std::string> printable(const char* field, std::size_t size) {
  const std::size_t length = std::find(field, field + size, '\0') - field;
  for (std::size_t i = 0; i < length; ++i)
    if (field[i] < 0x20 || field[i] > 0x7e) return std::nullopt;
  return std::string(field, length);
}

/// The two frames of a device name <From>To<To> (one "To" before a capital letter), as
/// (to, from); nullopt when there is not exactly one such "To" or a side is empty.
std::optional<std::pair<std::string, std::string>> transform_frames(const std::string& device) {
  std::size_t split = std::string::npos;
  for (std::size_t i = 1; i + 2 < device.size(); ++i) {
    if (device.compare(i, 2, "To") != 0 || !std::isupper(static_cast<unsigned char>(device[i + 2]))) continue;
    if (split != std::string::npos) return std::nullopt;
    split = i;
  }
  if (split == std::string::npos) return std::nullopt;
  return std::pair{device.substr(split + 2), device.substr(0, split)};
}

}  // namespace

std::uint64_t body_limit_bytes(std::string_view type) {
  if (type == "TRANSFORM") return kTransformBodyBytes;
  if (type == "TDATA") return kTrackingElementsLimit * IGTL_TDATA_ELEMENT_SIZE;
  if (type == "IMAGE") return kImageHeaderBytes + dds::kMaxFramePixels;
  return kOtherBodyLimitBytes;
}

Result<MessageHeader> parse_header(std::span<const std::uint8_t> bytes) {
  if (bytes.size() != kHeaderBytes)
    return Error{.message = "an OpenIGTLink header is 58 bytes, not " + std::to_string(bytes.size()),
                 .field = "header"};
  igtl_header raw;
  static_assert(sizeof(raw) == kHeaderBytes);
  std::memcpy(&raw, bytes.data(), kHeaderBytes);
  igtl_header_convert_byte_order(&raw);
  MessageHeader header;
  header.version = raw.version;
  if (header.version != 1 && header.version != 2)
    return Error{.message = "header version " + std::to_string(header.version) + " (this bridge reads 1 and 2)",
                 .field = "version"};
  const auto type = printable(raw.name, sizeof(raw.name));
  const auto device = printable(raw.device_name, sizeof(raw.device_name));
  if (!type || type->empty()) return Error{.message = "the message type is not printable text", .field = "type"};
  if (!device) return Error{.message = "the device name is not printable text", .field = "device_name"};
  header.type = *type;
  header.device = *device;
  const std::uint64_t seconds = raw.timestamp >> 32;
  const std::uint32_t fraction = static_cast<std::uint32_t>(raw.timestamp & 0xffffffffU);
  header.timestamp_ns = static_cast<TimeNs>(seconds * 1'000'000'000ULL + igtl_frac_to_nanosec(fraction));
  header.body_bytes = raw.body_size;
  header.body_crc = raw.crc;
  const std::uint64_t limit =
      body_limit_bytes(header.type) + (header.version == 2 ? kExtendedHeaderBytes + kMetadataLimitBytes : 0);
  if (header.body_bytes > limit)
    return Error{.message = header.type + " body of " + std::to_string(header.body_bytes) + " bytes (at most " +
                            std::to_string(limit) + ") from '" + header.device + "'",
                 .field = "body_size"};
  return header;
}

Status check_body(const MessageHeader& header, std::span<const std::uint8_t> body) {
  if (body.size() != header.body_bytes)
    return Error{.message = "body of " + std::to_string(body.size()) + " bytes where the header announced " +
                            std::to_string(header.body_bytes),
                 .field = "body_size"};
  const igtl_uint64 crc = crc64(const_cast<unsigned char*>(body.data()), body.size(), 0);
  if (crc != header.body_crc)
    return Error{.message = header.type + " from '" + header.device + "' fails its CRC-64", .field = "crc"};
  return Done{};
}

Result<ContentRange> content_range(const MessageHeader& header, std::span<const std::uint8_t> body) {
  if (header.version == 1) return ContentRange{0, body.size()};
  const auto refused = [&](const std::string& what, const char* field) {
    return Error{.message = header.type + " from '" + header.device + "' (v3): " + what, .field = field};
  };
  if (body.size() < kExtendedHeaderBytes) return refused("no room for its extended header", "extended_header_size");
  const std::uint64_t extended_bytes = big_endian(body.data(), 2);
  const std::uint64_t metadata_header_bytes = big_endian(body.data() + 2, 2);
  const std::uint64_t metadata_bytes = big_endian(body.data() + 4, 4);
  if (extended_bytes < kExtendedHeaderBytes)
    return refused("an extended header of " + std::to_string(extended_bytes) + " bytes (12 at least)",
                   "extended_header_size");
  if (metadata_header_bytes + metadata_bytes > kMetadataLimitBytes)
    return refused(std::to_string(metadata_header_bytes + metadata_bytes) + " bytes of metadata (at most " +
                       std::to_string(kMetadataLimitBytes) + ")",
                   "meta_data_size");
  if (extended_bytes + metadata_header_bytes + metadata_bytes > body.size())
    return refused("extended header and metadata of " +
                       std::to_string(extended_bytes + metadata_header_bytes + metadata_bytes) +
                       " bytes in a body of " + std::to_string(body.size()),
                   "meta_data_size");
  const std::size_t metadata_at = body.size() - metadata_header_bytes - metadata_bytes;
  if (metadata_header_bytes > 0) {  // an index count, then an entry per key: their sizes add up to the metadata's
    const std::uint8_t* index = body.data() + metadata_at;
    const std::uint64_t count = metadata_header_bytes >= 2 ? big_endian(index, 2) : 0;
    if (metadata_header_bytes != 2 + kMetadataEntryBytes * count)
      return refused("a metadata header of " + std::to_string(metadata_header_bytes) + " bytes for " +
                         std::to_string(count) + " entries",
                     "meta_data_header_size");
    std::uint64_t listed_bytes = 0;
    for (std::uint64_t k = 0; k < count; ++k) {
      const std::uint8_t* entry = index + 2 + kMetadataEntryBytes * k;
      listed_bytes += big_endian(entry, 2) + big_endian(entry + 4, 4);  // key size, value size
    }
    if (listed_bytes != metadata_bytes)
      return refused("metadata entries of " + std::to_string(listed_bytes) + " bytes where " +
                         std::to_string(metadata_bytes) + " were announced",
                     "meta_data_size");
  } else if (metadata_bytes > 0) {
    return refused("metadata without a metadata header", "meta_data_header_size");
  }
  return ContentRange{static_cast<std::size_t>(extended_bytes), metadata_at - static_cast<std::size_t>(extended_bytes)};
}

namespace {

/// A 48-byte TRANSFORM matrix named `name` (<From>To<To>) as the pose of `tool_id` at `time_ns`.
Result<dds::ToolPose> tool_pose_from_matrix(const std::string& name, std::span<const std::uint8_t> matrix,
                                            TimeNs time_ns, std::uint32_t tool_id) {
  igtl_float32 m[12];
  std::memcpy(m, matrix.data(), sizeof(m));
  igtl_transform_convert_byte_order(m);
  if (!std::all_of(m, m + 12, [](float v) { return std::isfinite(v); }))
    return Error{.message = "the transform holds a non-finite entry", .field = name};
  Eigen::Matrix3d rotation;  // columns first on the wire: R11 R21 R31 R12 ...
  for (int c = 0; c < 3; ++c)
    for (int r = 0; r < 3; ++r) rotation(r, c) = m[3 * c + r];
  if ((rotation.transpose() * rotation - Eigen::Matrix3d::Identity()).norm() > 1e-3 || rotation.determinant() < 0.0)
    return Error{.message = "the transform's upper 3x3 is not a rotation", .field = name};
  const Eigen::Vector3d translation_mm(m[9], m[10], m[11]);
  if (translation_mm.norm() > kLargestTranslationMm)
    return Error{.message = "a translation of " + std::to_string(translation_mm.norm()) + " mm", .field = name};
  const auto frames = transform_frames(name);
  if (!frames)
    return Error{.message = "the name is not <From>To<To> with one 'To' before a capital letter", .field = name};
  dds::ToolPose pose;  // a name has at most 20 characters: each frame name fits
  dds::set_frame_name(pose.frame_to, frames->first);
  dds::set_frame_name(pose.frame_from, frames->second);
  pose.tool_id = tool_id;
  pose.source_time_ns = time_ns;
  const Eigen::Quaterniond q(rotation);
  pose.orientation_wxyz = {q.w(), q.x(), q.y(), q.z()};
  for (int i = 0; i < 3; ++i) pose.position_m[static_cast<std::size_t>(i)] = 1e-3 * translation_mm[i];
  pose.quality = 1.0f;
  return pose;
}

}  // namespace

Result<dds::ToolPose> tool_pose_from_transform(const MessageHeader& header, std::span<const std::uint8_t> content,
                                               std::uint32_t tool_id) {
  if (header.type != "TRANSFORM" || content.size() != kTransformBodyBytes)
    return Error{.message = "not a 48-byte TRANSFORM body", .field = header.device};
  return tool_pose_from_matrix(header.device, content, header.timestamp_ns, tool_id);
}

Result<std::vector<TrackingElement>> tracking_elements(const MessageHeader& header,
                                                       std::span<const std::uint8_t> content) {
  const std::size_t count = content.size() / IGTL_TDATA_ELEMENT_SIZE;
  if (header.type != "TDATA" || content.size() % IGTL_TDATA_ELEMENT_SIZE != 0 || count == 0 ||
      count > kTrackingElementsLimit)
    return Error{.message = "TDATA from '" + header.device + "' of " + std::to_string(content.size()) +
                            " bytes: not 1 to " + std::to_string(kTrackingElementsLimit) + " elements of 70 bytes",
                 .field = "body_size"};
  std::vector<TrackingElement> elements;
  elements.reserve(count);
  for (std::size_t k = 0; k < count; ++k) {
    const std::span<const std::uint8_t> element = content.subspan(k * IGTL_TDATA_ELEMENT_SIZE, IGTL_TDATA_ELEMENT_SIZE);
    const auto name = printable(reinterpret_cast<const char*>(element.data()), IGTL_TDATA_LEN_NAME);
    if (!name || name->empty())
      return Error{.message = "TDATA from '" + header.device + "': element " + std::to_string(k) +
                              "'s name is not printable text",
                   .field = "name"};
    elements.push_back({*name, element.subspan(IGTL_TDATA_LEN_NAME + 2, kTransformBodyBytes)});
  }
  return elements;
}

Result<dds::ToolPose> tool_pose_from_element(const MessageHeader& header, const TrackingElement& element,
                                             std::uint32_t tool_id) {
  return tool_pose_from_matrix(element.name, element.matrix, header.timestamp_ns, tool_id);
}

Status ultrasound_frame_from_image(const MessageHeader& header, std::span<const std::uint8_t> content,
                                   std::uint32_t probe_tool_id, dds::UltrasoundFrame& frame) {
  const auto refused = [&](const std::string& what, const char* field) {
    return Error{.message = "IMAGE from '" + header.device + "': " + what, .field = field};
  };
  if (header.type != "IMAGE" || content.size() < kImageHeaderBytes)
    return refused("shorter than its image header", "body_size");
  igtl_image_header image;
  static_assert(sizeof(image) == kImageHeaderBytes);
  std::memcpy(&image, content.data(), kImageHeaderBytes);
  igtl_image_convert_byte_order(&image);
  if (image.num_components != 1)
    return refused(std::to_string(image.num_components) + " components (1)", "num_components");
  if (image.scalar_type != IGTL_IMAGE_STYPE_TYPE_UINT8 && image.scalar_type != IGTL_IMAGE_STYPE_TYPE_INT8)
    return refused("scalar type " + std::to_string(image.scalar_type) + " (8-bit only)", "scalar_type");
  if (image.size[2] != 1) return refused(std::to_string(image.size[2]) + " slices (a frame has 1)", "size");
  for (int i = 0; i < 3; ++i)
    if (image.subvol_offset[i] != 0 || image.subvol_size[i] != image.size[i])
      return refused("a sub-volume (the bridge takes whole frames)", "subvol_size");
  const std::uint64_t pixels = std::uint64_t{image.size[0]} * image.size[1];
  if (pixels == 0 || pixels > dds::kMaxFramePixels)
    return refused(std::to_string(image.size[0]) + " x " + std::to_string(image.size[1]) + " pixels (1 to " +
                       std::to_string(dds::kMaxFramePixels) + ")",
                   "size");
  if (content.size() != kImageHeaderBytes + pixels)
    return refused("content of " + std::to_string(content.size()) + " bytes for " + std::to_string(pixels) + " pixels",
                   "body_size");
  float spacing_mm[3], origin_mm[3], along_i[3], along_j[3], along_k[3];
  igtl_image_get_matrix(spacing_mm, origin_mm, along_i, along_j, along_k, &image);
  for (int i = 0; i < 2; ++i)
    if (!std::isfinite(spacing_mm[i]) || !(spacing_mm[i] > 1e-4f && spacing_mm[i] < 10.0f))
      return refused("a pixel spacing of " + std::to_string(spacing_mm[i]) + " mm (0.0001 to 10)", "matrix");
  frame.sequence_number = 0;
  frame.source_time_ns = header.timestamp_ns;
  frame.probe_tool_id = probe_tool_id;
  frame.width_px = image.size[0];
  frame.height_px = image.size[1];
  frame.pixel_spacing_m = {1e-3 * spacing_mm[0], 1e-3 * spacing_mm[1]};
  frame.depth_m = frame.height_px * frame.pixel_spacing_m[1];
  std::copy_n(content.begin() + kImageHeaderBytes, pixels, frame.pixels.begin());
  return Done{};
}

}  // namespace nav::igtl
