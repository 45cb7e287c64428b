#pragma once
// OpenIGTLink messages as the tests make and read them with OpenIGTLink itself, the
// independent encoder and decoder the bridge's own code is checked against (header-only:
// shared by tests/igtl and tests/bridge).
#include <gtest/gtest.h>
#include <igtlImageMessage.h>
#include <igtlTransformMessage.h>

#include <cstdint>
#include <cstring>
#include <string>
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
