// The NDI combined API on the wire: CRC-16 against its published check value, BX and TX
// replies encoded and decoded for every tool state, and corrupted replies refused.
#include <gtest/gtest.h>

#include "nav/trackers/ndi_protocol.hpp"

namespace nav::trackers::ndi {
namespace {

TrackingReply sample_reply() {
  TrackingReply reply;
  HandleRecord ok{
      0x0A, ToolState::ok, {0.5, 0.5, -0.5, 0.5}, {12.34, -567.89, -1234.5}, 0.1234, kPortOccupied | kPortEnabled, 77};
  HandleRecord partly{0x0B,
                      ToolState::partly_out_of_volume,
                      {1.0, 0.0, 0.0, 0.0},
                      {1.0, 2.0, -3.0},
                      0.3,
                      kPortOccupied | kPortEnabled | kPortPartlyOutOfVolume,
                      77};
  HandleRecord missing{0x0C, ToolState::missing, {1.0, 0.0, 0.0, 0.0}, {}, 0.0, kPortOccupied | kPortEnabled, 77};
  HandleRecord disabled{0x0D, ToolState::disabled, {1.0, 0.0, 0.0, 0.0}, {}, 0.0, 0, 0};
  reply.handles = {ok, partly, missing, disabled};
  reply.system_status = 0x0001;
  return reply;
}

TEST(NdiProtocol, Crc16IsTheArcCrc) {
  EXPECT_EQ(crc16("123456789"), 0xBB3D);  // CRC-16/ARC check value
  EXPECT_EQ(crc16(""), 0x0000);
  EXPECT_EQ(
      frame_command("INIT", ""), "INIT:" + std::string() + [] {
        char text[8];
        std::snprintf(text, sizeof text, "%04X", crc16("INIT:"));
        return std::string(text);
      }() + "\r");
  auto body = check_reply(frame_reply("OKAY").substr(0, 8));
  ASSERT_TRUE(body.ok());
  EXPECT_EQ(body.value(), "OKAY");
  EXPECT_FALSE(check_reply("OKAX" + frame_reply("OKAY").substr(4, 4)).ok());
}

TEST(NdiProtocol, BxRoundTripKeepsEveryState) {
  const TrackingReply reply = sample_reply();
  auto decoded = decode_bx(encode_bx(reply));
  ASSERT_TRUE(decoded.ok()) << decoded.error().describe();
  ASSERT_EQ(decoded.value().handles.size(), 4u);
  EXPECT_EQ(decoded.value().system_status, 1);
  for (std::size_t i = 0; i < 4; ++i) {
    const HandleRecord& in = reply.handles[i];
    const HandleRecord& out = decoded.value().handles[i];
    EXPECT_EQ(out.handle, in.handle);
    EXPECT_EQ(out.state, in.state);
    if (!has_pose(in.state)) continue;
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(out.position_mm[k], in.position_mm[k], 1e-4 * std::abs(in.position_mm[k]));
    for (int k = 0; k < 4; ++k) EXPECT_NEAR(out.orientation_wxyz[k], in.orientation_wxyz[k], 1e-7);
    EXPECT_EQ(out.frame_number, 77u);
  }
}

TEST(NdiProtocol, TxRoundTripAtTheFormatsResolution) {
  const TrackingReply reply = sample_reply();
  const std::string body = encode_tx(reply);
  EXPECT_NE(body.find("0C"
                      "MISSING"),
            std::string::npos);
  EXPECT_NE(body.find("0DDISABLED\n"), std::string::npos);
  auto decoded = decode_tx(body);
  ASSERT_TRUE(decoded.ok()) << decoded.error().describe();
  ASSERT_EQ(decoded.value().handles.size(), 4u);
  const HandleRecord& ok = decoded.value().handles[0];
  EXPECT_EQ(ok.state, ToolState::ok);
  EXPECT_NEAR(ok.position_mm[1], -567.89, 0.005);  // 0.01 mm resolution
  EXPECT_NEAR(ok.orientation_wxyz[2], -0.5, 0.5e-4);
  EXPECT_NEAR(ok.error_mm, 0.1234, 0.5e-4);
  EXPECT_EQ(decoded.value().handles[1].state, ToolState::partly_out_of_volume);
  EXPECT_EQ(decoded.value().handles[2].state, ToolState::missing);
  EXPECT_EQ(decoded.value().handles[3].state, ToolState::disabled);
}

TEST(NdiProtocol, CorruptRepliesAreRefused) {
  std::string bx = encode_bx(sample_reply());
  std::string flipped = bx;
  flipped[10] = static_cast<char>(flipped[10] ^ 0x40);
  auto body_crc = decode_bx(flipped);
  ASSERT_FALSE(body_crc.ok());
  EXPECT_EQ(body_crc.error().field, "BX body");
  flipped = bx;
  flipped[2] = static_cast<char>(flipped[2] + 1);
  EXPECT_EQ(decode_bx(flipped).error().field, "BX header");
  EXPECT_FALSE(decode_bx(bx.substr(0, bx.size() - 1)).ok());
  EXPECT_FALSE(decode_tx("01"
                         "0A"
                         "+1000x")
                   .ok());
  EXPECT_FALSE(decode_tx(encode_tx(sample_reply()) + "X").ok());
  auto phsr = decode_phsr(encode_phsr({{0x01, 0x031}, {0x0A, 0x001}}));
  ASSERT_TRUE(phsr.ok());
  EXPECT_EQ(phsr.value()[1].handle, 0x0A);
  EXPECT_FALSE(decode_phsr("02"
                           "01031")
                   .ok());
}

}  // namespace
}  // namespace nav::trackers::ndi
