#pragma once
// OpenIGTLink messages as the bridge reads them off a stream: the 58-byte header (header
// version 1 of protocol v1/v2, or 2 of protocol v3) checked before any body is read; a v3
// body's extended header and metadata sizes checked to find its content; and the contents the
// station takes in (TRANSFORM, TDATA, IMAGE) checked against their header, size and CRC before
// any field is used. Plain types only: OpenIGTLink's headers stay in igtl_wire.cpp.
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "nav/core/clock.hpp"
#include "nav/core/error.hpp"
#include "nav/dds/samples.hpp"

namespace nav::igtl {

inline constexpr std::size_t kHeaderBytes = 58;
inline constexpr std::size_t kExtendedHeaderBytes = 12;                    ///< a v3 body's first field group
inline constexpr std::size_t kMetadataLimitBytes = std::size_t{64} << 10;  ///< a v3 body's metadata, at most
inline constexpr std::size_t kTrackingElementsLimit = 64;                  ///< tools in one TDATA, at most

/// What a message's header says, once checked.
struct MessageHeader {
  std::uint16_t version = 0;
  std::string type;    ///< e.g. "TRANSFORM", "IMAGE"
  std::string device;  ///< e.g. "ProbeToTracker" (PLUS names a transform <From>To<To>)
  TimeNs timestamp_ns = 0;
  std::uint64_t body_bytes = 0;
  std::uint64_t body_crc = 0;
};

/// The largest content the bridge reads of a message type (IMAGE: its 72-byte image header and
/// one dds::kMaxFramePixels frame; TRANSFORM: 48 bytes; TDATA: kTrackingElementsLimit tools of
/// 70 bytes; others it only skips: 64 KiB). A v3 body may add its extended header and
/// kMetadataLimitBytes of metadata.
std::uint64_t body_limit_bytes(std::string_view type);

/// The header in `bytes` (kHeaderBytes of them). Errors name the field: a version other than
/// 1 or 2, a type or device name that is not printable ASCII, a body above its type's limit.
Result<MessageHeader> parse_header(std::span<const std::uint8_t> bytes);

/// Whether `body` is the one `header` announced: its size and its CRC-64.
Status check_body(const MessageHeader& header, std::span<const std::uint8_t> body);

/// Where a body's content lies: all of the body (header version 1), or what a v3 body holds
/// between its extended header and its metadata (header version 2).
struct ContentRange {
  std::size_t offset = 0;
  std::size_t bytes = 0;
};

/// The content range of `body` (checked against `header`). Errors, v3 only, name the field: an
/// extended header shorter than 12 bytes, sizes that do not fit in the body, metadata beyond
/// its limit, a metadata header whose entries do not add up to the metadata's size.
Result<ContentRange> content_range(const MessageHeader& header, std::span<const std::uint8_t> body);

/// A TRANSFORM content as the pose of the tool `tool_id` (frame names from the device name:
/// "ProbeToTracker" is tracker_from_probe), stamped with the header's time. Errors: a
/// non-finite entry, a rotation that is not one (|R^T R - I| above 1e-3), a translation
/// beyond 10 m (OpenIGTLink sends millimetres: the pose is in metres).
Result<dds::ToolPose> tool_pose_from_transform(const MessageHeader& header, std::span<const std::uint8_t> content,
                                               std::uint32_t tool_id);

/// One tool of a TDATA message: its name and its 48-byte matrix, as on the wire.
struct TrackingElement {
  std::string name;  ///< e.g. "StylusToTracker"
  std::span<const std::uint8_t> matrix;
};

/// The tools of a TDATA content (1 to kTrackingElementsLimit elements of 70 bytes). Errors
/// name the field: a size that is not whole elements, a name that is not printable text.
Result<std::vector<TrackingElement>> tracking_elements(const MessageHeader& header,
                                                       std::span<const std::uint8_t> content);

/// One TDATA element as the pose of `tool_id`, as tool_pose_from_transform reads a TRANSFORM
/// named like the element (frames from its name), stamped with the message's time.
Result<dds::ToolPose> tool_pose_from_element(const MessageHeader& header, const TrackingElement& element,
                                             std::uint32_t tool_id);

/// An IMAGE content as one ultrasound frame of the probe `probe_tool_id`: a whole 2-D image
/// (size k = 1, no sub-volume) of one 8-bit component, at most dds::kMaxFramePixels pixels,
/// its pixel spacing the lengths of the image matrix's first two columns (mm on the wire, m
/// in the frame), its depth the image's height times the spacing along a column. Errors name
/// the field that is not so. The frame is filled in place (it holds 1 MiB).
Status ultrasound_frame_from_image(const MessageHeader& header, std::span<const std::uint8_t> content,
                                   std::uint32_t probe_tool_id, dds::UltrasoundFrame& frame);

}  // namespace nav::igtl
