// The NDI driver against the simulated NDI device over a pseudo-terminal (as over a serial
// line) and over TCP loopback: initialisation of the port handles, BX and TX polling, tool
// states, poses equal to the device's within the formats' resolution, device errors reported.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <fstream>

#include "loopback_listener.hpp"
#include "nav/trackers/ndi_simulator.hpp"
#include "nav/trackers/ndi_tracker.hpp"

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

/// A passive tool's definition: `size` bytes of a pattern seeded by `seed` (a .rom file's bytes).
std::string definition(std::size_t size, int seed) {
  std::string bytes;
  for (std::size_t i = 0; i < size; ++i)
    bytes += static_cast<char>((i * 31 + static_cast<std::size_t>(seed) * 17) % 251);
  return bytes;
}

TEST(NdiTracker, NegotiatesTheSerialRateWithCommAndTheDeviceHearsOnlyItsOwnRate) {
  auto pty = open_pseudo_terminal();
  ASSERT_TRUE(pty.ok());
  auto connection = Connection::open_serial(pty.value().slave_path);
  ASSERT_TRUE(connection.ok()) << connection.error().describe();
  // The device listens at 9600, as after power-on, and only to a host at its rate.
  NdiDeviceServer server(pty.value().master_fd, SimulatedNdiDevice(station_tools()), pty.value().slave_path);
  ASSERT_TRUE(connection.value().set_serial_speed(115200).ok());
  connection.value().reply_timeout_ns = 100 * kNsPerMs;
  EXPECT_FALSE(connection.value().command("INIT", "").ok());  // unheard at the wrong rate
  EXPECT_EQ(server.garbled_lines(), 1u);
  connection.value().reply_timeout_ns = 2 * kNsPerSecond;

  ASSERT_TRUE(negotiate_serial(connection.value(), 115200).ok());
  auto tracker = NdiTracker::start(std::move(connection).value());  // now heard at 115200 only
  ASSERT_TRUE(tracker.ok()) << tracker.error().describe();
  auto samples = tracker.value().poll(ReplyFormat::bx, 0);
  ASSERT_TRUE(samples.ok()) << samples.error().describe();
  EXPECT_EQ(samples.value().size(), 2u);
  EXPECT_EQ(server.garbled_lines(), 1u);

  // The protocol's rate codes: 115200 is 5, 921600 6, 230400 A; rates without a host speed fail.
  EXPECT_EQ(comm_arguments(115200), "50000");
  EXPECT_EQ(comm_arguments(921600), "60000");
  EXPECT_EQ(comm_arguments(230400), "A0000");
  EXPECT_FALSE(comm_arguments(14400));
  EXPECT_EQ(comm_baud("50000"), 115200);
  EXPECT_FALSE(comm_baud("50001"));  // a handshake the driver never asks for
  EXPECT_FALSE(comm_baud("9"));
}

TEST(NdiTracker, ADeviceThatDoesNotAnswerAt9600AndSendsNoResetIsNamed) {
  // A device left at 115200 by an earlier session: INIT at 9600 goes unheard, and the serial
  // break that would reset it cannot cross a pseudo-terminal, so no RESET comes.
  auto pty = open_pseudo_terminal();
  ASSERT_TRUE(pty.ok());
  auto connection = Connection::open_serial(pty.value().slave_path);
  ASSERT_TRUE(connection.ok());
  NdiDeviceServer server(pty.value().master_fd, SimulatedNdiDevice(station_tools(), kNsPerSecond / 60, 115200),
                         pty.value().slave_path);
  connection.value().reply_timeout_ns = 300 * kNsPerMs;
  const Status negotiated = negotiate_serial(connection.value(), 115200);
  ASSERT_FALSE(negotiated.ok());
  EXPECT_NE(negotiated.error().describe().find("no RESET after a serial break"), std::string::npos)
      << negotiated.error().describe();
  EXPECT_NE(negotiated.error().describe().find(pty.value().slave_path), std::string::npos)
      << negotiated.error().describe();
  EXPECT_FALSE(negotiate_serial(connection.value(), 14400).ok());  // no such host rate: refused before anything is sent
}

TEST(NdiTracker, LoadsPassiveToolsFromTheirDefinitionsAndTracksThem) {
  std::vector<SimulatedNdiTool> tools = station_tools();
  SimulatedNdiTool passive;
  passive.definition = definition(752, 1);  // a 752-byte .rom: 12 chunks, the last one padded
  passive.trajectory.centre_m = {-0.2, 0.1, -0.9};
  tools.push_back(passive);
  SimulatedNdiTool other = passive;
  other.definition = definition(1024, 2);
  other.trajectory.centre_m = {0.3, 0.0, -1.0};
  tools.push_back(other);

  auto pty = open_pseudo_terminal();
  ASSERT_TRUE(pty.ok());
  auto connection = Connection::open_serial(pty.value().slave_path);
  ASSERT_TRUE(connection.ok());
  NdiDeviceServer server(pty.value().master_fd, SimulatedNdiDevice(tools), pty.value().slave_path);
  auto tracker = NdiTracker::start(std::move(connection).value(), {other.definition, passive.definition});
  ASSERT_TRUE(tracker.ok()) << tracker.error().describe();
  ASSERT_EQ(tracker.value().passive_handles().size(), 2u);
  EXPECT_EQ(tracker.value().handles().size(), 4u);  // the two active tools and the two loaded
  auto samples = tracker.value().poll(ReplyFormat::bx, 0);
  ASSERT_TRUE(samples.ok()) << samples.error().describe();
  // Each loaded handle tracks the tool whose definition it got: near its trajectory's centre.
  const auto near = [&](std::uint8_t handle, const std::array<double, 3>& centre) {
    for (const TrackerSample& s : samples.value())
      if (s.tool_id == handle)
        return has_pose(s.state) &&
               std::hypot(s.position_m[0] - centre[0], s.position_m[1] - centre[1], s.position_m[2] - centre[2]) < 0.1;
    return false;
  };
  EXPECT_TRUE(near(tracker.value().passive_handles()[0], other.trajectory.centre_m));
  EXPECT_TRUE(near(tracker.value().passive_handles()[1], passive.trajectory.centre_m));

  // A definition the device has no tool for: PINIT fails and the error names it.
  auto pty2 = open_pseudo_terminal();
  ASSERT_TRUE(pty2.ok());
  auto connection2 = Connection::open_serial(pty2.value().slave_path);
  ASSERT_TRUE(connection2.ok());
  NdiDeviceServer server2(pty2.value().master_fd, SimulatedNdiDevice(tools), pty2.value().slave_path);
  std::string damaged = passive.definition;
  damaged[100] = static_cast<char>(damaged[100] ^ 0x5A);
  auto refused = NdiTracker::start(std::move(connection2).value(), {damaged});
  ASSERT_FALSE(refused.ok());
  EXPECT_NE(refused.error().describe().find("PINIT"), std::string::npos) << refused.error().describe();
  EXPECT_NE(refused.error().describe().find("ERROR0E"), std::string::npos) << refused.error().describe();
}

TEST(NdiTracker, ToolDefinitionFilesAreReadWhole) {
  const std::string path = ::testing::TempDir() + "tool.rom";
  { std::ofstream(path, std::ios::binary) << definition(752, 3); }
  auto read = read_tool_definition(path);
  ASSERT_TRUE(read.ok()) << read.error().describe();
  EXPECT_EQ(read.value(), definition(752, 3));
  { std::ofstream(path, std::ios::binary) << definition(1025, 3); }
  auto too_long = read_tool_definition(path);
  ASSERT_FALSE(too_long.ok());
  EXPECT_NE(too_long.error().describe().find("1025 bytes"), std::string::npos);
  { std::ofstream(path, std::ios::binary); }
  EXPECT_FALSE(read_tool_definition(path).ok());
  auto missing = read_tool_definition(path + ".missing");
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.error().describe().find("tool.rom.missing"), std::string::npos);

  // PVWR's arguments carry the handle, the address and 64 bytes; a misplaced chunk is refused.
  const RomWrite chunk{0x0A, 0x40, definition(64, 4)};
  auto decoded = decode_pvwr(encode_pvwr(chunk));
  ASSERT_TRUE(decoded.ok()) << decoded.error().describe();
  EXPECT_EQ(decoded.value().handle, 0x0A);
  EXPECT_EQ(decoded.value().address, 0x40u);
  EXPECT_EQ(decoded.value().bytes, chunk.bytes);
  EXPECT_FALSE(decode_pvwr(encode_pvwr({0x0A, 0x20, chunk.bytes})).ok());   // not on a chunk
  EXPECT_FALSE(decode_pvwr(encode_pvwr({0x0A, 0x400, chunk.bytes})).ok());  // past the 1024 bytes
  EXPECT_FALSE(decode_pvwr("0A0040XY").ok());
}

}  // namespace
}  // namespace nav::trackers::ndi
