// The bridge's outbound side as 3D Slicer meets it: a client written with OpenIGTLink's own
// socket connects to the bridge, the station publishes its outputs on DDS, and the client
// unpacks (with OpenIGTLink) the deformed surface with the scene's triangles, the needle's
// centreline and tip, the tumour now and ahead with their radii, and the health line. The
// recorded byte stream is walked by hand against the protocol's header layout (version 1,
// 12-byte type, 20-byte device name, 64-bit time stamp, body size and CRC-64, big-endian),
// with a CRC computed here. A surface of another scene is refused and counted; a display that
// leaves is dropped.
#include <gtest/gtest.h>
#include <igtlPointMessage.h>
#include <igtlPolyDataMessage.h>
#include <igtlStringMessage.h>
#include <igtlTransformMessage.h>

#include <algorithm>
#include <cstring>
#include <list>
#include <map>
#include <memory>
#include <span>
#include <thread>

#include "bridge_test_support.hpp"
#include "nav/bridge/igtl_bridge.hpp"
#include "nav/core/health.hpp"
#include "nav/dds/dds_node.hpp"
#include "nav/dds/health_text.hpp"
#include "nav/igtl/wall_clock.hpp"
#include "nav/station/display_surface.hpp"
#include "nav/station/station_dds.hpp"
#include "nav/station/station_liver.hpp"

namespace nav::bridge {
namespace {

using nav::testing::bridge_scene;
using nav::testing::SlicerClient;
using nav::testing::unpack_into;
using nav::testing::wait_until;

constexpr std::uint32_t kDomain = 221;
constexpr TimeNs kTimeoutNs = 10 * kNsPerSecond;
constexpr std::size_t kHeaderBytes = igtl::kHeaderBytes;

/// CRC-64 of the protocol (ECMA-182 polynomial, most significant bit first, no reflection,
/// zero start and end), computed bit by bit: independent of OpenIGTLink's table.
std::uint64_t crc64_ecma182(std::span<const std::uint8_t> bytes) {
  std::uint64_t crc = 0;
  for (const std::uint8_t byte : bytes) {
    crc ^= std::uint64_t{byte} << 56;
    for (int bit = 0; bit < 8; ++bit) crc = (crc >> 63) != 0 ? (crc << 1) ^ 0x42F0E1EBA9EA3693ULL : crc << 1;
  }
  return crc;
}

std::uint64_t big_endian(const std::uint8_t* bytes, int count) {
  std::uint64_t value = 0;
  for (int i = 0; i < count; ++i) value = (value << 8) | bytes[i];
  return value;
}

dds::Covariance3 diagonal(double a, double b, double c) { return {a, 0, 0, 0, b, 0, 0, 0, c}; }

TEST(IgtlBridgeOut, ADisplayReadsTheStationsOutputsAsSlicerDoes) {
  const station::Scene scene = bridge_scene(kDomain, "  displays: 127.0.0.1:0\n");
  auto bridge = IgtlBridge::open(scene);
  ASSERT_TRUE(bridge.ok()) << bridge.error().describe();
  auto mesh = station::make_station_mesh(scene);
  ASSERT_TRUE(mesh.ok());
  auto surface = station::make_display_surface(mesh.value());
  ASSERT_TRUE(surface.ok());
  auto made = station::make_station_node(kDomain, "test_station", station::topic_names(scene.topics), scene.network);
  ASSERT_TRUE(made.ok());
  dds::DdsNode& station_node = *made.value();
  for (const Status& s :
       {station_node.advertise<dds::DeformedSurface>(), station_node.advertise<dds::NeedleState>(),
        station_node.advertise<dds::TargetPrediction>(), station_node.advertise<dds::StationHealth>()})
    ASSERT_TRUE(s.ok());
  const nav::testing::RunningBridge running(*bridge.value());
  for (const dds::Topic topic : {dds::Topic::deformed_surface, dds::Topic::needle_state, dds::Topic::target_prediction,
                                 dds::Topic::station_health})
    ASSERT_TRUE(station_node.wait_for_match(topic, 1, kTimeoutNs));

  SlicerClient slicer;
  ASSERT_EQ(slicer.socket->ConnectToServer("127.0.0.1", bridge.value()->displays_port()), 0);
  slicer.socket->SetReceiveTimeout(200);
  ASSERT_TRUE(wait_until([&] { return bridge.value()->totals().displays_connected == 1; }));

  const TimeNs now_ns = MonotonicClock().now_ns();
  auto deformed = std::make_unique<dds::DeformedSurface>();
  deformed->source_time_ns = now_ns;
  deformed->surface_id = station::kLiverSurfaceId;
  deformed->vertex_count = static_cast<std::uint32_t>(surface.value().rest_m.size());
  for (std::size_t i = 0; i < deformed->vertex_count; ++i)
    for (std::size_t k = 0; k < 3; ++k)
      deformed->vertex_positions_m[i][k] = static_cast<float>(surface.value().rest_m[i][k] + (k == 2 ? 0.005 : 0.0));
  dds::NeedleState needle;
  needle.source_time_ns = now_ns;
  needle.tool_id = 1;
  needle.point_count = 5;
  for (std::size_t i = 0; i < 5; ++i) needle.shape_points_m[i] = {0.01 * i, 0.1, -0.02};
  dds::TargetPrediction tumour_now;
  tumour_now.source_time_ns = now_ns;
  tumour_now.position_m = {-0.04, -0.005, 0.003};
  tumour_now.covariance_m2 = diagonal(4e-6, 1e-6, 1e-6);  // 2 mm along x
  dds::TargetPrediction tumour_ahead = tumour_now;
  tumour_ahead.horizon_ns = 50 * kNsPerMs;
  tumour_ahead.position_m = {-0.04, -0.005, 0.008};
  tumour_ahead.covariance_m2 = diagonal(1e-6, 9e-6, 1e-6);  // 3 mm along y
  dds::StationHealth health;
  health.source_time_ns = now_ns;
  health.mode = dds::StationMode::degraded;
  health.flags = static_cast<std::uint32_t>(HealthFlag::stale_input);
  health.boundary.malformed = 2;
  // Written again until all arrived, as a station streams them: Fast DDS may lose a sample
  // written at once after the writer matched (1 run in 4 here when they went once).
  const auto write_all = [&] {
    return station_node.write(*deformed) && station_node.write(needle) && station_node.write(tumour_now) &&
           station_node.write(tumour_ahead) && station_node.write(health);
  };
  const std::vector<std::string> expected{"LiverSurface", "Needle", "NeedleTipToReference", "Tumour", "StationHealth"};
  ASSERT_TRUE(wait_until([&] {
    if (!write_all()) return false;
    slicer.receive();
    for (const std::string& name : expected)
      if (slicer.newest.count(name) == 0) return false;
    // the tumour's two points may come in one message or two
    ::igtl::PointMessage::Pointer points = ::igtl::PointMessage::New();
    unpack_into(slicer.newest["Tumour"], points);
    return points->GetNumberOfPointElement() == 2;
  })) << "received "
      << slicer.newest.size() << " of the 5 device names";

  ::igtl::PolyDataMessage::Pointer liver = ::igtl::PolyDataMessage::New();
  unpack_into(slicer.newest["LiverSurface"], liver);
  ASSERT_EQ(liver->GetPoints()->GetNumberOfPoints(), static_cast<int>(deformed->vertex_count));
  ASSERT_NE(liver->GetPolygons(), nullptr);
  EXPECT_EQ(liver->GetPolygons()->GetNumberOfCells(), surface.value().triangles.size());
  igtlFloat32 first[3];
  liver->GetPoints()->GetPoint(0, first);
  EXPECT_NEAR(first[2], 1e3 * deformed->vertex_positions_m[0][2], 1e-3);  // millimetres
  std::list<igtlUint32> cell;
  liver->GetPolygons()->GetCell(0, cell);
  const std::array<std::int32_t, 3>& triangle = surface.value().triangles[0];
  EXPECT_EQ(std::vector<igtlUint32>(cell.begin(), cell.end()),
            (std::vector<igtlUint32>{static_cast<igtlUint32>(triangle[0]), static_cast<igtlUint32>(triangle[1]),
                                     static_cast<igtlUint32>(triangle[2])}));

  ::igtl::PolyDataMessage::Pointer centreline = ::igtl::PolyDataMessage::New();
  unpack_into(slicer.newest["Needle"], centreline);
  EXPECT_EQ(centreline->GetPoints()->GetNumberOfPoints(), 5);
  ASSERT_NE(centreline->GetLines(), nullptr);
  EXPECT_EQ(centreline->GetLines()->GetCellSize(0), 5u);
  ::igtl::TransformMessage::Pointer tip = ::igtl::TransformMessage::New();
  unpack_into(slicer.newest["NeedleTipToReference"], tip);
  ::igtl::Matrix4x4 m;
  tip->GetMatrix(m);
  EXPECT_NEAR(m[0][3], 40.0f, 1e-3);
  EXPECT_NEAR(m[1][3], 100.0f, 1e-3);
  EXPECT_NEAR(m[2][3], -20.0f, 1e-3);

  ::igtl::PointMessage::Pointer tumour = ::igtl::PointMessage::New();
  unpack_into(slicer.newest["Tumour"], tumour);
  ::igtl::PointElement::Pointer now_point, ahead_point;
  tumour->GetPointElement(0, now_point);
  tumour->GetPointElement(1, ahead_point);
  EXPECT_STREQ(now_point->GetName(), "now");
  EXPECT_NEAR(now_point->GetRadius(), 2.0f, 1e-4);
  EXPECT_STREQ(ahead_point->GetName(), "ahead");
  EXPECT_NEAR(ahead_point->GetRadius(), 3.0f, 1e-4);
  float ahead_mm[3];
  ahead_point->GetPosition(ahead_mm);
  EXPECT_NEAR(ahead_mm[2], 8.0f, 1e-3);

  ::igtl::StringMessage::Pointer words = ::igtl::StringMessage::New();
  unpack_into(slicer.newest["StationHealth"], words);
  EXPECT_EQ(std::string(words->GetString()), dds::health_summary(health));
  unsigned seconds = 0, fraction = 0;
  words->GetTimeStamp(&seconds, &fraction);
  EXPECT_NEAR(static_cast<double>(seconds) - 1e-9 * static_cast<double>(igtl::wall_now_ns()), 0.0, 5.0)
      << "stamped in wall-clock time";

  // The recorded stream, walked by hand: every header's layout and every body's CRC.
  std::size_t at = 0, messages = 0;
  while (at + kHeaderBytes <= slicer.recorded.size()) {
    const std::uint8_t* h = slicer.recorded.data() + at;
    EXPECT_EQ(big_endian(h, 2), 1u) << "header version";
    const std::string type(reinterpret_cast<const char*>(h + 2), strnlen(reinterpret_cast<const char*>(h + 2), 12));
    const std::string device(reinterpret_cast<const char*>(h + 14), strnlen(reinterpret_cast<const char*>(h + 14), 20));
    const std::uint64_t body_bytes = big_endian(h + 42, 8);
    EXPECT_TRUE(type == "POLYDATA" || type == "TRANSFORM" || type == "POINT" || type == "STRING") << type;
    EXPECT_TRUE(std::find(expected.begin(), expected.end(), device) != expected.end()) << device;
    EXPECT_NEAR(static_cast<double>(big_endian(h + 34, 4)) - 1e-9 * static_cast<double>(igtl::wall_now_ns()), 0.0, 5.0);
    ASSERT_LE(at + kHeaderBytes + body_bytes, slicer.recorded.size());
    EXPECT_EQ(big_endian(h + 50, 8), crc64_ecma182({h + kHeaderBytes, body_bytes})) << device << " CRC";
    at += kHeaderBytes + body_bytes;
    ++messages;
  }
  EXPECT_EQ(at, slicer.recorded.size());
  EXPECT_GE(messages, expected.size());
  std::printf("recorded %zu messages, %zu bytes\n", messages, slicer.recorded.size());

  deformed->vertex_count = 10;  // another scene's surface: refused, counted
  ASSERT_TRUE(station_node.write(*deformed));
  ASSERT_TRUE(wait_until([&] { return bridge.value()->totals().refused_out == 1; }));
  slicer.socket->CloseSocket();
  ASSERT_TRUE(wait_until([&] { return bridge.value()->totals().displays_dropped == 1; }));
  EXPECT_GE(bridge.value()->totals().messages_out, expected.size());
}

}  // namespace
}  // namespace nav::bridge
