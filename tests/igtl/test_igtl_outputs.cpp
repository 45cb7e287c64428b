// The station's outputs packed for 3D Slicer, read back by OpenIGTLink's own unpacking (an
// independent decoder): names, millimetres, the needle's polyline, the surface's triangles,
// the tumour's points with their radius, the health's text, the time stamp; and through the
// bridge's own reader, which checks their headers and CRCs.
#include <gtest/gtest.h>

#include <igtlImageMessage.h>
#include <igtlPointMessage.h>
#include <igtlPolyDataMessage.h>
#include <igtlStringMessage.h>
#include <igtlTransformMessage.h>

#include <cmath>
#include <cstring>
#include <list>
#include <memory>
#include <vector>

#include "igtl_test_messages.hpp"
#include "nav/igtl/igtl_outputs.hpp"
#include "nav/igtl/igtl_wire.hpp"

namespace nav::igtl {
namespace {

constexpr TimeNs kTimeNs = 1'700'000'000'250'000'000;  // .25 s past a whole second

using nav::testing::unpack_into;

/// What the bridge's own reader makes of `bytes`: their checked header.
MessageHeader checked_header(const std::vector<std::uint8_t>& bytes) {
  const auto header = parse_header(std::span(bytes).first(kHeaderBytes));
  EXPECT_TRUE(header.ok());
  if (!header.ok()) return {};
  EXPECT_TRUE(check_body(header.value(), std::span(bytes).subspan(kHeaderBytes)).ok());
  return header.value();
}

TEST(IgtlOutputs, TheNeedleTipIsATransformInMillimetres) {
  const double half = std::sqrt(0.5);  // 90 degrees about z
  const auto bytes = pack_transform(kNeedleTipDevice, {half, 0.0, 0.0, half}, {0.01, -0.02, 0.15}, kTimeNs);
  ::igtl::TransformMessage::Pointer message = ::igtl::TransformMessage::New();
  unpack_into(bytes, message);
  EXPECT_STREQ(message->GetDeviceName(), "NeedleTipToReference");
  ::igtl::Matrix4x4 m;
  message->GetMatrix(m);
  EXPECT_NEAR(m[0][3], 10.0f, 1e-4);
  EXPECT_NEAR(m[1][3], -20.0f, 1e-4);
  EXPECT_NEAR(m[2][3], 150.0f, 1e-4);
  EXPECT_NEAR(m[0][1], -1.0f, 1e-6);  // x' = -y
  EXPECT_NEAR(m[1][0], 1.0f, 1e-6);
  unsigned seconds = 0, fraction = 0;
  message->GetTimeStamp(&seconds, &fraction);
  EXPECT_EQ(seconds, 1'700'000'000U);
  EXPECT_NEAR(fraction / 4294967296.0, 0.25, 1e-9);
  EXPECT_NEAR(static_cast<double>(checked_header(bytes).timestamp_ns), static_cast<double>(kTimeNs), 1.0);
}

TEST(IgtlOutputs, TheTumourIsAPointNowAndAheadWithItsRadius) {
  const std::vector<NamedPoint> points{{"now", {0.1, 0.2, 0.3}, 0.002}, {"in 50 ms", {0.1, 0.2, 0.31}, 0.003}};
  const auto bytes = pack_points(kTumourDevice, points, kTimeNs);
  ::igtl::PointMessage::Pointer message = ::igtl::PointMessage::New();
  unpack_into(bytes, message);
  ASSERT_EQ(message->GetNumberOfPointElement(), 2);
  ::igtl::PointElement::Pointer ahead;
  message->GetPointElement(1, ahead);
  EXPECT_STREQ(ahead->GetName(), "in 50 ms");
  float p[3];
  ahead->GetPosition(p);
  EXPECT_NEAR(p[2], 310.0f, 1e-3);
  EXPECT_NEAR(ahead->GetRadius(), 3.0f, 1e-5);
  EXPECT_EQ(checked_header(bytes).type, "POINT");
}

TEST(IgtlOutputs, TheNeedleIsAPolylineAndTheLiverATriangleSurface) {
  const std::vector<std::array<float, 3>> needle{{0.0f, 0.0f, 0.0f}, {0.0f, 0.0f, 0.05f}, {0.001f, 0.0f, 0.1f}};
  const auto line_bytes = pack_polydata(kNeedleDevice, needle, {}, kTimeNs);
  ::igtl::PolyDataMessage::Pointer line = ::igtl::PolyDataMessage::New();
  unpack_into(line_bytes, line);
  ASSERT_EQ(line->GetPoints()->GetNumberOfPoints(), 3);
  ASSERT_EQ(line->GetLines()->GetNumberOfCells(), 1U);
  std::list<igtlUint32> cell;
  line->GetLines()->GetCell(0, cell);
  EXPECT_EQ(cell, (std::list<igtlUint32>{0, 1, 2}));
  float tip[3];
  line->GetPoints()->GetPoint(2, tip);
  EXPECT_NEAR(tip[0], 1.0f, 1e-4);
  EXPECT_NEAR(tip[2], 100.0f, 1e-3);

  const std::vector<std::array<float, 3>> corners{{0, 0, 0}, {0.01f, 0, 0}, {0, 0.01f, 0}, {0, 0, 0.01f}};
  const std::vector<std::array<std::uint32_t, 3>> faces{{0, 2, 1}, {0, 1, 3}, {1, 2, 3}, {0, 3, 2}};
  const auto surface_bytes = pack_polydata(kLiverSurfaceDevice, corners, faces, kTimeNs);
  ::igtl::PolyDataMessage::Pointer surface = ::igtl::PolyDataMessage::New();
  unpack_into(surface_bytes, surface);
  ASSERT_EQ(surface->GetPolygons()->GetNumberOfCells(), 4U);
  igtlUint32 face[3];
  surface->GetPolygons()->GetCell(2, face);
  EXPECT_EQ(face[0], 1U);
  EXPECT_EQ(face[2], 3U);
  EXPECT_EQ(checked_header(surface_bytes).device, "LiverSurface");
}

TEST(IgtlOutputs, TheHealthIsAString) {
  const auto bytes = pack_string(kHealthDevice, "station DEGRADED | stale_input", kTimeNs);
  ::igtl::StringMessage::Pointer message = ::igtl::StringMessage::New();
  unpack_into(bytes, message);
  EXPECT_STREQ(message->GetString(), "station DEGRADED | stale_input");
  EXPECT_EQ(checked_header(bytes).device, "StationHealth");
}

TEST(IgtlOutputs, AnImageCarriesItsPixelsAndSpacingToOpenIgtlinkAndBackToAFrame) {
  std::vector<std::uint8_t> pixels(40 * 30);
  for (std::size_t i = 0; i < pixels.size(); ++i) pixels[i] = static_cast<std::uint8_t>(i * 7);
  const auto bytes = pack_image("Image_Reference", 40, 30, pixels, {0.25, 0.5}, kTimeNs);
  ::igtl::ImageMessage::Pointer message = ::igtl::ImageMessage::New();
  unpack_into(bytes, message);
  int size[3];
  message->GetDimensions(size);
  EXPECT_EQ(size[0], 40);
  EXPECT_EQ(size[1], 30);
  float spacing[3];
  message->GetSpacing(spacing);
  EXPECT_FLOAT_EQ(spacing[0], 0.25f);
  EXPECT_FLOAT_EQ(spacing[1], 0.5f);
  EXPECT_EQ(std::memcmp(message->GetScalarPointer(), pixels.data(), pixels.size()), 0);
  // and through the bridge's reader, as the station's frame
  const MessageHeader header = checked_header(bytes);
  auto frame = std::make_unique<dds::UltrasoundFrame>();
  ASSERT_TRUE(ultrasound_frame_from_image(header, std::span(bytes).subspan(kHeaderBytes), 2, *frame).ok());
  EXPECT_EQ(frame->width_px, 40u);
  EXPECT_DOUBLE_EQ(frame->pixel_spacing_m[1], 0.5e-3);
  EXPECT_DOUBLE_EQ(frame->depth_m, 30 * 0.5e-3);
  EXPECT_EQ(frame->pixels[39 * 1 + 40 * 29], pixels[39 + 40 * 29]);
}

}  // namespace
}  // namespace nav::igtl
