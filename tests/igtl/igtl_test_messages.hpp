#pragma once
// OpenIGTLink messages as the tests make and read them with OpenIGTLink itself, the
// independent encoder and decoder the bridge's own code is checked against (header-only:
// shared by tests/igtl and tests/bridge).
#include <gtest/gtest.h>
#include <igtlImageMessage.h>
#include <igtlTrackingDataMessage.h>
#include <igtlTransformMessage.h>
#include <igtl_util.h>

#include <array>
#include <cstdint>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

#include "nav/core/clock.hpp"
#include "nav/igtl/igtl_wire.hpp"

namespace nav::testing {

/// The bytes of a message packed by OpenIGTLink.
inline std::vector<std::uint8_t> packed_bytes(::igtl::MessageBase& message) {
  message.Pack();
  const auto* bytes = static_cast<const std::uint8_t*>(message.GetPackPointer());
  return {bytes, bytes + message.GetPackSize()};
}

/// `time_ns` as OpenIGTLink's seconds and 2^-32 fractions.
inline void stamp_message(::igtl::MessageBase& message, TimeNs time_ns) {
  message.SetTimeStamp(static_cast<unsigned>(time_ns / kNsPerSecond),
                       static_cast<unsigned>(((time_ns % kNsPerSecond) << 32) / kNsPerSecond));
}

/// A TRANSFORM `device` of `matrix` (row-major 3x4, translation in mm), stamped `time_ns`.
inline std::vector<std::uint8_t> transform_bytes(const std::string& device, const float (&matrix)[3][4],
                                                 TimeNs time_ns) {
  ::igtl::TransformMessage::Pointer message = ::igtl::TransformMessage::New();
  message->SetDeviceName(device.c_str());
  ::igtl::Matrix4x4 m;
  ::igtl::IdentityMatrix(m);
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 4; ++c) m[r][c] = matrix[r][c];
  message->SetMatrix(m);
  stamp_message(*message, time_ns);
  return packed_bytes(*message);
}

/// An 8-bit IMAGE `device` of width x height pixels (value: (x + y) % 256) at the spacing in mm.
inline std::vector<std::uint8_t> image_bytes(const std::string& device, int width, int height, float spacing_x_mm,
                                             float spacing_y_mm, TimeNs time_ns) {
  ::igtl::ImageMessage::Pointer message = ::igtl::ImageMessage::New();
  message->SetDeviceName(device.c_str());
  message->SetDimensions(width, height, 1);
  message->SetSpacing(spacing_x_mm, spacing_y_mm, 1.0f);
  message->SetScalarTypeToUint8();
  message->AllocateScalars();
  auto* pixels = static_cast<std::uint8_t*>(message->GetScalarPointer());
  for (int y = 0; y < height; ++y)
    for (int x = 0; x < width; ++x) pixels[y * width + x] = static_cast<std::uint8_t>((x + y) % 256);
  stamp_message(*message, time_ns);
  return packed_bytes(*message);
}

/// One tool of a TDATA: its name and its row-major 3x4 matrix (translation in mm).
using TrackedTool = std::pair<std::string, std::array<std::array<float, 4>, 3>>;

/// A TDATA of `tools` (6-D instruments), stamped `time_ns`, packed by OpenIGTLink.
inline std::vector<std::uint8_t> tracking_bytes(const std::vector<TrackedTool>& tools, TimeNs time_ns) {
  ::igtl::TrackingDataMessage::Pointer message = ::igtl::TrackingDataMessage::New();
  message->SetDeviceName("Tracker");
  for (const auto& [name, matrix] : tools) {
    ::igtl::TrackingDataElement::Pointer element = ::igtl::TrackingDataElement::New();
    element->SetName(name.c_str());
    element->SetType(::igtl::TrackingDataElement::TYPE_6D);
    ::igtl::Matrix4x4 m;
    ::igtl::IdentityMatrix(m);
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c) m[r][c] = matrix[static_cast<std::size_t>(r)][static_cast<std::size_t>(c)];
    element->SetMatrix(m);
    message->AddTrackingDataElement(element);
  }
  stamp_message(*message, time_ns);
  return packed_bytes(*message);
}

/// `message` (one header-version-1 message) as protocol v3 sends it: header version 2; the body
/// its 12-byte extended header (message id 7), the content, then one metadata entry `key` =
/// `value` (US-ASCII); body size and CRC-64 made anew.
inline std::vector<std::uint8_t> as_version3(const std::vector<std::uint8_t>& message, const std::string& key,
                                             const std::string& value) {
  const auto big_endian = [](std::vector<std::uint8_t>& out, std::uint64_t v, int bytes) {
    for (int i = bytes - 1; i >= 0; --i) out.push_back(static_cast<std::uint8_t>(v >> (8 * i)));
  };
  std::vector<std::uint8_t> body;
  big_endian(body, 12, 2);                         // extended header size
  big_endian(body, 2 + 8, 2);                      // metadata header: an index count and one entry
  big_endian(body, key.size() + value.size(), 4);  // metadata
  big_endian(body, 7, 4);                          // message id
  body.insert(body.end(), message.begin() + igtl::kHeaderBytes, message.end());
  big_endian(body, 1, 2);             // one entry:
  big_endian(body, key.size(), 2);    //   its key's size,
  big_endian(body, 3, 2);             //   value encoding (US-ASCII, IANA MIBenum 3),
  big_endian(body, value.size(), 4);  //   its value's size
  body.insert(body.end(), key.begin(), key.end());
  body.insert(body.end(), value.begin(), value.end());
  std::vector<std::uint8_t> v3(message.begin(), message.begin() + 42);  // version, type, device, stamp
  v3[0] = 0;
  v3[1] = 2;
  big_endian(v3, body.size(), 8);
  big_endian(v3, crc64(body.data(), body.size(), 0), 8);
  v3.insert(v3.end(), body.begin(), body.end());
  return v3;
}

/// `bytes` (one whole message) unpacked by OpenIGTLink into `message` (of the type they
/// hold), its CRC checked.
template <typename MessagePointer>
void unpack_into(const std::vector<std::uint8_t>& bytes, MessagePointer& message) {
  ::igtl::MessageHeader::Pointer header = ::igtl::MessageHeader::New();
  header->InitPack();
  std::memcpy(header->GetPackPointer(), bytes.data(), igtl::kHeaderBytes);
  ASSERT_TRUE(header->Unpack() & ::igtl::MessageHeader::UNPACK_HEADER);
  message->SetMessageHeader(header);
  message->AllocatePack();
  ASSERT_EQ(static_cast<std::size_t>(message->GetPackBodySize()), bytes.size() - igtl::kHeaderBytes);
  std::memcpy(message->GetPackBodyPointer(), bytes.data() + igtl::kHeaderBytes, bytes.size() - igtl::kHeaderBytes);
  ASSERT_TRUE(message->Unpack(1) & ::igtl::MessageHeader::UNPACK_BODY);
}

}  // namespace nav::testing
