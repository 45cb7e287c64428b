// The NDI driver against the simulated NDI device over a pseudo-terminal (as over a serial
// line) and over TCP loopback: initialisation of the port handles, BX and TX polling, tool
// states, poses equal to the device's within the formats' resolution, device errors reported.
#include <gtest/gtest.h>

#include <unistd.h>

#include "nav/trackers/ndi_simulator.hpp"
#include "nav/trackers/ndi_tracker.hpp"
#include "loopback_listener.hpp"

namespace nav::trackers::ndi {
namespace {

std::vector<SimulatedNdiTool> station_tools() {
  SimulatedNdiTool needle;
  needle.handle = 0x01;
  needle.missing_every = 5;
  SimulatedNdiTool probe;
  probe.handle = 0x02;
  probe.trajectory.centre_m = {0.1, -0.05, -1.1};
  probe.partly_out_every = 3;
  return {needle, probe};
}

/// A simulated device on a pty and the driver connected to its slave side.
struct PtyLink {
  std::unique_ptr<NdiDeviceServer> server;
  std::optional<Connection> connection;
};

PtyLink open_pty_link() {
  PtyLink link;
  auto pty = open_pseudo_terminal();
  EXPECT_TRUE(pty.ok());
  auto connection = Connection::open_serial(pty.value().slave_path);
  EXPECT_TRUE(connection.ok()) << connection.error().describe();
  link.server = std::make_unique<NdiDeviceServer>(pty.value().master_fd, SimulatedNdiDevice(station_tools()));
  link.connection.emplace(std::move(connection).value());
  return link;
}

void expect_matches_device(const std::vector<TrackerSample>& samples, std::uint32_t frame, double tolerance_m) {
  ASSERT_EQ(samples.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    // The reference device's records are those of an enabled port at this frame.
    SimulatedNdiDevice device(station_tools());
    for (const char* line : {"PINIT 01", "PINIT 02", "PENA 01D", "PENA 02D"}) device.respond(line);
    const HandleRecord expected = device.record(i, frame);
    EXPECT_EQ(samples[i].tool_id, expected.handle);
    EXPECT_EQ(samples[i].state, expected.state) << "frame " << frame;
    EXPECT_EQ(samples[i].frame_number, frame);
    if (!has_pose(expected.state)) continue;
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(samples[i].position_m[k], expected.position_mm[k] * 1e-3, tolerance_m);
  }
}

TEST(NdiTracker, InitialisesAndPollsBxOverAPseudoTerminal) {
  PtyLink link = open_pty_link();
  auto tracker = NdiTracker::start(std::move(*link.connection));
  ASSERT_TRUE(tracker.ok()) << tracker.error().describe();
  EXPECT_EQ(tracker.value().handles(), (std::vector<std::uint8_t>{0x01, 0x02}));
  int missing = 0, partly = 0;
  for (std::uint32_t frame = 0; frame < 30; ++frame) {
    auto samples = tracker.value().poll(ReplyFormat::bx, frame);
    ASSERT_TRUE(samples.ok()) << samples.error().describe();
    expect_matches_device(samples.value(), frame, 1e-6);  // float32 of millimetres
    missing += samples.value()[0].state == ToolState::missing;
    partly += samples.value()[1].state == ToolState::partly_out_of_volume;
  }
  EXPECT_EQ(missing, 6);  // frames 0, 5, ..., 25
  EXPECT_EQ(partly, 10);  // frames 0, 3, ..., 27
  EXPECT_TRUE(tracker.value().stop().ok());
  auto after_stop = tracker.value().poll(ReplyFormat::bx, 0);
  ASSERT_FALSE(after_stop.ok());
  EXPECT_NE(after_stop.error().message.find("ERROR0C"), std::string::npos);
}

TEST(NdiTracker, PollsTxOverTcp) {
  const testing::LoopbackListener listener;
  auto connection = Connection::open_tcp("127.0.0.1", listener.port);
  ASSERT_TRUE(connection.ok()) << connection.error().describe();
  const int accepted = listener.accept();
  NdiDeviceServer server(accepted, SimulatedNdiDevice(station_tools()));
  auto tracker = NdiTracker::start(std::move(connection).value());
  ASSERT_TRUE(tracker.ok()) << tracker.error().describe();
  for (std::uint32_t frame = 0; frame < 10; ++frame) {
    auto samples = tracker.value().poll(ReplyFormat::tx, frame);
    ASSERT_TRUE(samples.ok()) << samples.error().describe();
    expect_matches_device(samples.value(), frame, 0.5e-5);  // TX: 0.01 mm
  }
}

TEST(NdiTracker, DeviceErrorsAndSilenceAreReported) {
  PtyLink link = open_pty_link();
  auto unknown = link.connection->command("FOO", "");
  ASSERT_FALSE(unknown.ok());
  EXPECT_EQ(unknown.error().field, "FOO");
  EXPECT_NE(unknown.error().message.find("ERROR01"), std::string::npos);
  auto not_tracking = link.connection->binary_command("BX", "0001");
  ASSERT_FALSE(not_tracking.ok());
  EXPECT_NE(not_tracking.error().message.find("ERROR0C"), std::string::npos);
  // A bad CRC on the command is refused by the device.
  SimulatedNdiDevice device(station_tools());
  EXPECT_EQ(device.respond("INIT:0000"), frame_reply("ERROR04"));
  EXPECT_EQ(device.respond("INIT "), frame_reply("OKAY"));
  // Nobody answering: a timeout, not a hang.
  auto pty = open_pseudo_terminal();
  ASSERT_TRUE(pty.ok());
  auto silent = Connection::open_serial(pty.value().slave_path);
  ASSERT_TRUE(silent.ok());
  silent.value().reply_timeout_ns = 50 * kNsPerMs;
  auto timed_out = silent.value().command("INIT", "");
  ASSERT_FALSE(timed_out.ok());
  EXPECT_NE(timed_out.error().message.find("timeout"), std::string::npos);
  ::close(pty.value().master_fd);
}

}  // namespace
}  // namespace nav::trackers::ndi
