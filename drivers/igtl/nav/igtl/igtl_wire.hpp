#pragma once
// OpenIGTLink messages as the bridge reads them off a stream: the 58-byte header (protocol
// v2, header version 1) checked before any body is read, and the bodies the station takes in
// (TRANSFORM, IMAGE) checked against their header, size and CRC before any field is used.
// Plain types only: OpenIGTLink's headers stay in igtl_wire.cpp.
#include <cstddef>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>

#include "nav/core/clock.hpp"
#include "nav/core/error.hpp"
#include "nav/dds/samples.hpp"

namespace nav::igtl {

inline constexpr std::size_t kHeaderBytes = 58;

/// What a message's header says, once checked.
struct MessageHeader {
  std::uint16_t version = 0;
  std::string type;    ///< e.g. "TRANSFORM", "IMAGE"
  std::string device;  ///< e.g. "ProbeToTracker" (PLUS names a transform <From>To<To>)
  TimeNs timestamp_ns = 0;
  std::uint64_t body_bytes = 0;
  std::uint64_t body_crc = 0;
};

/// The largest body the bridge reads of a message type (IMAGE: its 72-byte image header and
/// one dds::kMaxFramePixels frame; TRANSFORM: 48 bytes; others it only skips: 64 KiB).
std::uint64_t body_limit_bytes(std::string_view type);

/// The header in `bytes` (kHeaderBytes of them). Errors name the field: a version other than
/// 1, a type or device name that is not printable ASCII, a body above its type's limit.
Result<MessageHeader> parse_header(std::span<const std::uint8_t> bytes);

/// Whether `body` is the one `header` announced: its size and its CRC-64.
Status check_body(const MessageHeader& header, std::span<const std::uint8_t> body);

/// A TRANSFORM body as the pose of the tool `tool_id` (frame names from the device name:
/// "ProbeToTracker" is tracker_from_probe), stamped with the header's time. Errors: a
/// non-finite entry, a rotation that is not one (|R^T R - I| above 1e-3), a translation
/// beyond 10 m (OpenIGTLink sends millimetres: the pose is in metres).
Result<dds::ToolPose> tool_pose_from_transform(const MessageHeader& header, std::span<const std::uint8_t> body,
                                               std::uint32_t tool_id);

/// An IMAGE body as one ultrasound frame of the probe `probe_tool_id`: a whole 2-D image
/// (size k = 1, no sub-volume) of one 8-bit component, at most dds::kMaxFramePixels pixels,
/// its pixel spacing the lengths of the image matrix's first two columns (mm on the wire, m
/// in the frame), its depth the image's height times the spacing along a column. Errors name
/// the field that is not so. The frame is filled in place (it holds 1 MiB).
Status ultrasound_frame_from_image(const MessageHeader& header, std::span<const std::uint8_t> body,
                                   std::uint32_t probe_tool_id, dds::UltrasoundFrame& frame);

}  // namespace nav::igtl
