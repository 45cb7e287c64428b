// The bridge's reading of OpenIGTLink messages, against messages packed by OpenIGTLink's own
// library (an independent encoder): a TRANSFORM becomes the pose it describes (millimetres to
// metres, PLUS's <From>To<To> name to frames), and every header or body a sender could forge
// (oversized, wrong CRC, another version, unprintable names, not a rotation) is refused,
// naming the field, before its body is read or used.
#include <gtest/gtest.h>

#include <igtlImageMessage.h>
#include <igtlTransformMessage.h>

#include <cmath>
#include <cstring>
#include <memory>
#include <vector>

#include "igtl_test_messages.hpp"
#include "nav/igtl/igtl_wire.hpp"

namespace nav::igtl {
namespace {

/// A TRANSFORM packed by OpenIGTLink: a rotation of `angle_rad` about z and a translation in mm.
std::vector<std::uint8_t> packed_transform(const char* device, double angle_rad, const float (&translation_mm)[3],
                                           unsigned seconds = 1700000000, unsigned fraction = 0x80000000U) {
  ::igtl::TransformMessage::Pointer message = ::igtl::TransformMessage::New();
  message->SetDeviceName(device);
  ::igtl::Matrix4x4 matrix;
  ::igtl::IdentityMatrix(matrix);
  matrix[0][0] = static_cast<float>(std::cos(angle_rad));
  matrix[0][1] = static_cast<float>(-std::sin(angle_rad));
  matrix[1][0] = static_cast<float>(std::sin(angle_rad));
  matrix[1][1] = static_cast<float>(std::cos(angle_rad));
  for (int i = 0; i < 3; ++i) matrix[i][3] = translation_mm[i];
  message->SetMatrix(matrix);
  message->SetTimeStamp(seconds, fraction);
  return nav::testing::packed_bytes(*message);
}

/// An 8-bit IMAGE packed by OpenIGTLink: width x height pixels (value (3 i + j) mod 256),
/// spacing in mm, `slices` deep.
std::vector<std::uint8_t> packed_image(int width, int height, float spacing_x_mm, float spacing_y_mm, int slices = 1,
                                       int scalar_type = ::igtl::ImageMessage::TYPE_UINT8) {
  ::igtl::ImageMessage::Pointer message = ::igtl::ImageMessage::New();
  message->SetDeviceName("Image_Reference");
  message->SetDimensions(width, height, slices);
  message->SetSpacing(spacing_x_mm, spacing_y_mm, 1.0f);
  message->SetScalarType(scalar_type);
  message->AllocateScalars();
  auto* pixels = static_cast<std::uint8_t*>(message->GetScalarPointer());
  for (int k = 0; k < slices; ++k)
    for (int j = 0; j < height; ++j)
      for (int i = 0; i < width; ++i)
        pixels[(k * height + j) * width + i] = static_cast<std::uint8_t>((3 * i + j) % 256);
  return nav::testing::packed_bytes(*message);
}

std::span<const std::uint8_t> header_of(const std::vector<std::uint8_t>& message) {
  return std::span(message).first(kHeaderBytes);
}
std::span<const std::uint8_t> body_of(const std::vector<std::uint8_t>& message) {
  return std::span(message).subspan(kHeaderBytes);
}

TEST(IgtlWire, ATransformPackedByOpenIgtLinkIsThePoseItDescribes) {
  const auto message = packed_transform("ProbeToTracker", 0.5, {10.0f, -20.0f, 300.0f});
  const auto header = parse_header(header_of(message));
  ASSERT_TRUE(header.ok()) << header.error().describe();
  EXPECT_EQ(header.value().type, "TRANSFORM");
  EXPECT_EQ(header.value().device, "ProbeToTracker");
  EXPECT_EQ(header.value().body_bytes, 48U);
  EXPECT_NEAR(static_cast<double>(header.value().timestamp_ns), 1700000000.5e9, 1.0);
  ASSERT_TRUE(check_body(header.value(), body_of(message)).ok());
  const auto pose = tool_pose_from_transform(header.value(), body_of(message), 7);
  ASSERT_TRUE(pose.ok()) << pose.error().describe();
  EXPECT_EQ(pose.value().tool_id, 7U);
  EXPECT_STREQ(pose.value().frame_to.data(), "Tracker");
  EXPECT_STREQ(pose.value().frame_from.data(), "Probe");
  EXPECT_NEAR(pose.value().position_m[0], 0.010, 1e-9);
  EXPECT_NEAR(pose.value().position_m[1], -0.020, 1e-9);
  EXPECT_NEAR(pose.value().position_m[2], 0.300, 1e-7);
  // A rotation of 0.5 rad about z: w = cos 0.25, z = sin 0.25 (float on the wire: 1e-6).
  EXPECT_NEAR(pose.value().orientation_wxyz[0], std::cos(0.25), 1e-6);
  EXPECT_NEAR(pose.value().orientation_wxyz[3], std::sin(0.25), 1e-6);
  EXPECT_NEAR(pose.value().orientation_wxyz[1], 0.0, 1e-6);
}

TEST(IgtlWire, AnOversizedBodyIsRefusedFromItsHeaderAlone) {
  auto message = packed_transform("ProbeToTracker", 0.0, {0.0f, 0.0f, 0.0f});
  const std::uint8_t huge[8] = {0x7f, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff, 0xff};
  std::memcpy(message.data() + 42, huge, sizeof(huge));  // body_size: 8 EiB
  const auto header = parse_header(header_of(message));
  ASSERT_FALSE(header.ok());
  EXPECT_EQ(header.error().field, "body_size");
  EXPECT_NE(header.error().message.find("ProbeToTracker"), std::string::npos) << header.error().message;
}

TEST(IgtlWire, ABodyThatFailsItsCrcIsRefused) {
  auto message = packed_transform("ProbeToTracker", 0.0, {1.0f, 2.0f, 3.0f});
  message.back() ^= 0x01;
  const auto header = parse_header(header_of(message));
  ASSERT_TRUE(header.ok());
  const Status checked = check_body(header.value(), body_of(message));
  ASSERT_FALSE(checked.ok());
  EXPECT_EQ(checked.error().field, "crc");
}

TEST(IgtlWire, AnotherHeaderVersionOrUnprintableNamesAreRefusedByField) {
  auto versioned = packed_transform("ProbeToTracker", 0.0, {0.0f, 0.0f, 0.0f});
  versioned[1] = 3;
  ASSERT_FALSE(parse_header(header_of(versioned)).ok());
  EXPECT_EQ(parse_header(header_of(versioned)).error().field, "version");
  auto named = packed_transform("ProbeToTracker", 0.0, {0.0f, 0.0f, 0.0f});
  named[14] = 0x07;  // the device name's first byte
  EXPECT_EQ(parse_header(header_of(named)).error().field, "device_name");
  EXPECT_FALSE(parse_header(std::span(named).first(20)).ok());
}

TEST(IgtlWire, ATransformThatIsNotAPoseIsRefusedNamingItsDevice) {
  const float origin[3] = {0.0f, 0.0f, 0.0f};
  for (const char* device : {"ProbeTracker", "AToBToC"}) {  // no frames, two
    const auto message = packed_transform(device, 0.0, origin);
    const auto header = parse_header(header_of(message));
    ASSERT_TRUE(header.ok());
    const auto pose = tool_pose_from_transform(header.value(), body_of(message), 1);
    ASSERT_FALSE(pose.ok()) << device;
    EXPECT_EQ(pose.error().field, device);
  }
  const auto far = packed_transform("ProbeToTracker", 0.0, {0.0f, 0.0f, 2.0e7f});  // 20 km
  const auto far_header = parse_header(header_of(far));
  ASSERT_TRUE(far_header.ok());
  EXPECT_FALSE(tool_pose_from_transform(far_header.value(), body_of(far), 1).ok());
  auto scaled = packed_transform("ProbeToTracker", 0.0, origin);
  const std::uint8_t two[4] = {0x40, 0x00, 0x00, 0x00};  // R11 = 2.0f: not a rotation
  std::memcpy(scaled.data() + kHeaderBytes, two, sizeof(two));
  const auto scaled_header = parse_header(header_of(scaled));
  ASSERT_TRUE(scaled_header.ok());
  const auto scaled_pose = tool_pose_from_transform(scaled_header.value(), body_of(scaled), 1);
  ASSERT_FALSE(scaled_pose.ok());
  EXPECT_NE(scaled_pose.error().message.find("not a rotation"), std::string::npos);
}

TEST(IgtlWire, AnImagePackedByOpenIgtLinkIsTheFrameItHolds) {
  const auto message = packed_image(64, 48, 0.2f, 0.25f);
  const auto header = parse_header(header_of(message));
  ASSERT_TRUE(header.ok()) << header.error().describe();
  ASSERT_TRUE(check_body(header.value(), body_of(message)).ok());
  auto frame = std::make_unique<dds::UltrasoundFrame>();
  const Status read = ultrasound_frame_from_image(header.value(), body_of(message), 2, *frame);
  ASSERT_TRUE(read.ok()) << read.error().describe();
  EXPECT_EQ(frame->width_px, 64U);
  EXPECT_EQ(frame->height_px, 48U);
  EXPECT_EQ(frame->probe_tool_id, 2U);
  EXPECT_NEAR(frame->pixel_spacing_m[0], 0.2e-3, 1e-9);
  EXPECT_NEAR(frame->pixel_spacing_m[1], 0.25e-3, 1e-9);
  EXPECT_NEAR(frame->depth_m, 48 * 0.25e-3, 1e-9);
  for (int j = 0; j < 48; ++j)
    for (int i = 0; i < 64; ++i) ASSERT_EQ(frame->pixels[j * 64 + i], (3 * i + j) % 256) << i << ", " << j;
}

TEST(IgtlWire, AnImageTheStationCannotTakeIsRefusedByField) {
  auto frame = std::make_unique<dds::UltrasoundFrame>();
  const auto refused_field = [&](const std::vector<std::uint8_t>& message) -> std::string {
    const auto header = parse_header(header_of(message));
    if (!header.ok()) return header.error().field;
    const Status read = ultrasound_frame_from_image(header.value(), body_of(message), 2, *frame);
    return read.ok() ? "" : read.error().field;
  };
  EXPECT_EQ(refused_field(packed_image(16, 16, 0.2f, 0.2f, 2)), "size");  // a volume
  EXPECT_EQ(refused_field(packed_image(16, 16, 0.2f, 0.2f, 1, ::igtl::ImageMessage::TYPE_UINT16)), "scalar_type");
  EXPECT_EQ(refused_field(packed_image(16, 16, 0.0f, 0.2f)), "matrix");         // no spacing
  EXPECT_EQ(refused_field(packed_image(1100, 1000, 0.2f, 0.2f)), "body_size");  // above 1 MiB: from its header
  // A header that says 16 x 16 over a body of other size: refused before a pixel is read.
  auto short_body = packed_image(16, 16, 0.2f, 0.2f);
  short_body.resize(short_body.size() - 10);
  const auto header = parse_header(header_of(short_body));
  ASSERT_TRUE(header.ok());
  const Status read = ultrasound_frame_from_image(header.value(), body_of(short_body), 2, *frame);
  ASSERT_FALSE(read.ok());
  EXPECT_EQ(read.error().field, "body_size");
}

}  // namespace
}  // namespace nav::igtl
