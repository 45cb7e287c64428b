// The bridge's reading of OpenIGTLink messages, against messages packed by OpenIGTLink's own
// library (an independent encoder): a TRANSFORM, or a TDATA element, becomes the pose it
// describes (millimetres to metres, PLUS's <From>To<To> name to frames); a protocol-v3 message
// (laid out here from the v3 specification) is read through its extended header and metadata to
// its content; and every header or body a sender could forge (oversized, wrong CRC, another
// version, unprintable names, not a rotation, v3 sizes that do not add up) is refused, naming
// the field, before its body is read or used.
#include <gtest/gtest.h>

#include <igtlImageMessage.h>
#include <igtlTransformMessage.h>

#include <array>
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

TEST(IgtlWire, AVersion3MessageIsReadThroughItsExtendedHeaderToItsContent) {
  const auto v1 = packed_transform("ProbeToTracker", 0.5, {10.0f, -20.0f, 300.0f});
  const auto v3 = nav::testing::as_version3(v1, "Status", "OK");
  const auto header = parse_header(header_of(v3));
  ASSERT_TRUE(header.ok()) << header.error().describe();
  EXPECT_EQ(header.value().version, 2);
  EXPECT_EQ(header.value().body_bytes, 12u + 48u + 10u + 8u);  // extended header, content, metadata header, metadata
  ASSERT_TRUE(check_body(header.value(), body_of(v3)).ok());
  const auto range = content_range(header.value(), body_of(v3));
  ASSERT_TRUE(range.ok()) << range.error().describe();
  EXPECT_EQ(range.value().offset, 12u);
  EXPECT_EQ(range.value().bytes, 48u);
  const auto pose = tool_pose_from_transform(header.value(), body_of(v3).subspan(12, 48), 7);
  const auto same = tool_pose_from_transform(parse_header(header_of(v1)).value(), body_of(v1), 7);
  ASSERT_TRUE(pose.ok() && same.ok());
  EXPECT_EQ(pose.value().position_m, same.value().position_m);
  EXPECT_EQ(pose.value().orientation_wxyz, same.value().orientation_wxyz);
  // a version-1 body is all content
  const auto whole = content_range(parse_header(header_of(v1)).value(), body_of(v1));
  ASSERT_TRUE(whole.ok());
  EXPECT_EQ(whole.value().offset, 0u);
  EXPECT_EQ(whole.value().bytes, 48u);
}

TEST(IgtlWire, Version3SizesThatDoNotAddUpAreRefusedByField) {
  const auto v3 = nav::testing::as_version3(packed_transform("ProbeToTracker", 0.0, {0, 0, 0}), "Status", "OK");
  const auto refused_field = [](std::vector<std::uint8_t> message, std::size_t at, std::uint8_t value) {
    message[kHeaderBytes + at] = value;  // a byte of the extended header or the metadata header
    const auto range = content_range(parse_header(header_of(message)).value(), body_of(message));
    return range.ok() ? std::string() : range.error().field;
  };
  EXPECT_EQ(refused_field(v3, 1, 4), "extended_header_size");      // 4 bytes: shorter than itself
  EXPECT_EQ(refused_field(v3, 1, 200), "meta_data_size");          // beyond the body
  EXPECT_EQ(refused_field(v3, 12 + 48 + 9, 3), "meta_data_size");  // a value of 3 bytes listed: 9 in all, 8 announced
  EXPECT_EQ(refused_field(v3, 12 + 48 + 1, 2), "meta_data_header_size");  // two entries in room for one
  auto truncated = v3;
  truncated.resize(kHeaderBytes + 6);
  EXPECT_EQ(content_range(parse_header(header_of(v3)).value(), body_of(truncated)).error().field,
            "extended_header_size");
  auto v4 = v3;
  v4[1] = 3;  // header version 3 does not exist
  EXPECT_EQ(parse_header(header_of(v4)).error().field, "version");
}

TEST(IgtlWire, TrackingDataIsReadElementByElement) {
  using Matrix = std::array<std::array<float, 4>, 3>;
  const Matrix quarter_turn{{{0, -1, 0, 10}, {1, 0, 0, 20}, {0, 0, 1, 30}}};
  const Matrix shifted{{{1, 0, 0, -5}, {0, 1, 0, 0}, {0, 0, 1, 250}}};
  const auto message = nav::testing::tracking_bytes({{"StylusToTracker", quarter_turn}, {"ProbeToTracker", shifted}},
                                                    1'700'000'000 * kNsPerSecond);
  const auto header = parse_header(header_of(message));
  ASSERT_TRUE(header.ok()) << header.error().describe();
  EXPECT_EQ(header.value().type, "TDATA");
  const auto elements = tracking_elements(header.value(), body_of(message));
  ASSERT_TRUE(elements.ok()) << elements.error().describe();
  ASSERT_EQ(elements.value().size(), 2u);
  EXPECT_EQ(elements.value()[0].name, "StylusToTracker");
  EXPECT_EQ(elements.value()[1].name, "ProbeToTracker");
  const auto stylus = tool_pose_from_element(header.value(), elements.value()[0], 1);
  const auto probe = tool_pose_from_element(header.value(), elements.value()[1], 2);
  ASSERT_TRUE(stylus.ok() && probe.ok());
  EXPECT_STREQ(stylus.value().frame_from.data(), "Stylus");
  EXPECT_STREQ(probe.value().frame_to.data(), "Tracker");
  EXPECT_NEAR(stylus.value().position_m[1], 0.020, 1e-9);
  EXPECT_NEAR(stylus.value().orientation_wxyz[3] * stylus.value().orientation_wxyz[0], 0.5,
              1e-6);  // 90 degrees about z
  EXPECT_NEAR(probe.value().position_m[2], 0.250, 1e-7);
  EXPECT_EQ(probe.value().source_time_ns, header.value().timestamp_ns);
  // not whole elements, or none
  EXPECT_EQ(tracking_elements(header.value(), body_of(message).first(71)).error().field, "body_size");
  EXPECT_EQ(tracking_elements(header.value(), body_of(message).first(0)).error().field, "body_size");
  // a name that is not text
  auto unnamed = message;
  unnamed[kHeaderBytes] = 0x01;
  EXPECT_EQ(tracking_elements(header.value(), body_of(unnamed)).error().field, "name");
}

}  // namespace
}  // namespace nav::igtl
