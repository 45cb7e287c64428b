// navdevice ndi, the NDI tracker as a device process, against the simulated NDI device (the
// combined API, CRC-checked) over a pseudo-terminal, as over a serial line, and over TCP
// loopback: the scene's port handles become its tools' ids and frame names on nav/tool_pose,
// a handle it does not map is counted and not published, missing tools are not published, and
// the process stops tracking (TSTOP) when done. Devices missing or misnamed are refused with
// the device's name.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <fstream>
#include <map>
#include <memory>
#include <thread>

#include "dds/child_process.hpp"
#include "dds/station_stand_in.hpp"
#include "loopback_listener.hpp"
#include "nav/dds/dds_node.hpp"
#include "nav/trackers/ndi_simulator.hpp"
#include "station/scene_text.hpp"
#include "support/test_data.hpp"

namespace nav::testing {
namespace {

using trackers::ndi::NdiDeviceServer;
using trackers::ndi::SimulatedNdiDevice;
using trackers::ndi::SimulatedNdiTool;

const std::string kBin = NAV_BIN_DIR;

/// Three tools on handles 1, 2 and 4: the probe on 1 (missing every 4th frame), the needle on
/// 2, and a tool on 4 that the scene does not map.
std::vector<SimulatedNdiTool> device_tools() {
  SimulatedNdiTool probe;
  probe.handle = 0x01;
  probe.trajectory.centre_m = {0.1, -0.05, -1.1};
  probe.missing_every = 4;
  SimulatedNdiTool needle;
  needle.handle = 0x02;
  SimulatedNdiTool other;
  other.handle = 0x04;
  return {probe, needle, other};
}

/// The demo scene with an NDI tracker on `connection` (YAML lines), its handles 2 (needle),
/// 1 (probe), 3 (respiratory) and its tools' ids 11, 12, 13.
std::string ndi_scene(const std::string& connection) {
  const std::string path = temporary_path("ndi_scene.yaml");
  const std::string simulated =
      "    kind: simulated\n    rate_hz: 60\n    latency_ms: 10\n    position_noise_m: 0.00025\n    "
      "rotation_noise_rad: 0.001\n    seed: 1\n";
  std::ofstream(path) << edited(movable_demo_text(), simulated,
                                "    kind: ndi\n" + connection +
                                    "    port_handles: {needle: 2, probe: 1, respiratory: 3}\n"
                                    "    tools: {needle: 11, probe: 12, respiratory: 13}\n    rate_hz: 60\n");
  return path;
}

/// Every pose `received`, by tool id.
std::map<std::uint32_t, std::vector<dds::ToolPose>> by_tool(
    const std::vector<std::unique_ptr<dds::ToolPose>>& received) {
  std::map<std::uint32_t, std::vector<dds::ToolPose>> poses;
  for (const auto& pose : received) poses[pose->tool_id].push_back(*pose);
  return poses;
}

/// Plays the device until it ends, standing in for the station on `domain` (the device waits
/// for its health), and returns every pose it published.
std::vector<std::unique_ptr<dds::ToolPose>> run_device(ChildProcess& device,
                                                       StationStandIn<dds::ToolPose, 1024>& station) {
  auto received = station.collect([&](const auto&) { return device.ended(); }, std::chrono::seconds(60));
  EXPECT_EQ(device.wait(std::chrono::seconds(30)), 0) << device.log();
  return received;
}

/// Checks the poses a 2 s run of navdevice ndi at 60 Hz published.
void expect_mapped_poses(const std::vector<std::unique_ptr<dds::ToolPose>>& received, const ChildProcess& device) {
  const auto poses = by_tool(received);
  std::printf("%s", device.log().c_str());
  EXPECT_EQ(poses.size(), 2u) << "only the mapped tools (11 and 12) are published";
  ASSERT_TRUE(poses.count(11) && poses.count(12));
  const auto& needle = poses.at(11);
  const auto& probe = poses.at(12);
  EXPECT_GE(needle.size(), 110u);  // 2 s at 60 Hz
  EXPECT_NEAR(static_cast<double>(probe.size()), 0.75 * static_cast<double>(needle.size()),
              0.05 * static_cast<double>(needle.size()));
  EXPECT_STREQ(needle.front().frame_from.data(), "needle_marker");
  EXPECT_STREQ(probe.front().frame_from.data(), "probe_marker");
  EXPECT_STREQ(probe.front().frame_to.data(), "tracker");
  for (const dds::ToolPose& p : probe)  // the probe's trajectory: a 5 cm circle about (0.1, -0.05, -1.1) m
    EXPECT_LT(std::hypot(p.position_m[0] - 0.1, p.position_m[1] + 0.05, p.position_m[2] + 1.1), 0.06);
  const std::string log = device.log();
  EXPECT_NE(log.find("3 port handles enabled"), std::string::npos);
  const std::size_t done = log.find("navdevice ndi: done after");
  ASSERT_NE(done, std::string::npos);
  const std::string last = log.substr(done);                // the final counts
  EXPECT_GT(number_after(last, "poses published, "), 0.0);  // tool samples without a pose: the probe's missing frames
  EXPECT_EQ(number_after(last, "without a pose, "), 0.0);   // refused by DDS
  EXPECT_GE(number_after(last, "refused, "), 100.0);        // samples of the unmapped handle 4
}

TEST(NavdeviceNdi, PublishesTheScenesToolsFromADeviceOnASerialLine) {
  auto pty = trackers::ndi::open_pseudo_terminal();
  ASSERT_TRUE(pty.ok()) << pty.error().describe();
  NdiDeviceServer server(pty.value().master_fd, SimulatedNdiDevice(device_tools()));
  StationStandIn<dds::ToolPose, 1024> station(181);
  ChildProcess device({kBin + "/navdevice", "ndi", "--scene", ndi_scene("    serial: " + pty.value().slave_path + "\n"),
                       "--seconds", "2", "--domain", "181"},
                      temporary_path("navdevice_ndi_serial.log"));
  expect_mapped_poses(run_device(device, station), device);
  EXPECT_GT(server.commands(), 100u);
}

TEST(NavdeviceNdi, NegotiatesTheScenesRateAndLoadsAPassiveToolFromItsRomFile) {
  // The respiratory marker is a passive tool: its definition file goes into the device, which
  // gives it a port handle; the device hears only a host at its own rate (9600, then COMM's).
  std::string rom;
  for (int i = 0; i < 700; ++i) rom += static_cast<char>((i * 37 + 11) % 256);
  const std::string rom_path = temporary_path("respiratory.rom");
  std::ofstream(rom_path, std::ios::binary) << rom;
  std::vector<SimulatedNdiTool> tools = device_tools();
  SimulatedNdiTool respiratory;
  respiratory.definition = rom;
  respiratory.trajectory.centre_m = {-0.2, 0.1, -0.9};
  tools.push_back(respiratory);
  auto pty = trackers::ndi::open_pseudo_terminal();
  ASSERT_TRUE(pty.ok()) << pty.error().describe();
  NdiDeviceServer server(pty.value().master_fd, SimulatedNdiDevice(tools), pty.value().slave_path);
  StationStandIn<dds::ToolPose, 1024> station(183);
  const std::string connection =
      "    serial: " + pty.value().slave_path + "\n    baud: 230400\n    rom_files: {respiratory: " + rom_path + "}\n";
  ChildProcess device(
      {kBin + "/navdevice", "ndi", "--scene", ndi_scene(connection), "--seconds", "2", "--domain", "183"},
      temporary_path("navdevice_ndi_passive.log"));
  const auto poses = by_tool(run_device(device, station));
  std::printf("%s", device.log().c_str());
  EXPECT_NE(device.log().find("4 port handles enabled"), std::string::npos);
  ASSERT_TRUE(poses.count(13)) << "the passive respiratory marker (tool 13)";
  EXPECT_GE(poses.at(13).size(), 110u);  // 2 s at 60 Hz, every poll heard at 230400
  for (const dds::ToolPose& p : poses.at(13))
    EXPECT_LT(std::hypot(p.position_m[0] + 0.2, p.position_m[1] - 0.1, p.position_m[2] + 0.9), 0.06);
  EXPECT_EQ(server.garbled_lines(), 0u);

  // A rate no NDI device and host share, and a definition file that is not there: named.
  ChildProcess bad_rate(
      {kBin + "/navstation", "--scene", ndi_scene("    serial: /dev/ttyUSB0\n    baud: 14400\n"), "--check"},
      temporary_path("navdevice_ndi_rate.log"));
  EXPECT_EQ(bad_rate.wait(std::chrono::seconds(120)), 1);
  EXPECT_NE(bad_rate.log().find("devices.tracker.baud"), std::string::npos) << bad_rate.log();
  ChildProcess no_rom(
      {kBin + "/navdevice", "ndi", "--scene",
       ndi_scene("    serial: " + pty.value().slave_path + "\n    rom_files: {needle: missing.rom}\n"), "--no-wait"},
      temporary_path("navdevice_ndi_no_rom.log"));
  EXPECT_EQ(no_rom.wait(std::chrono::seconds(30)), 1);
  EXPECT_NE(no_rom.log().find("missing.rom"), std::string::npos) << no_rom.log();
}

TEST(NavdeviceNdi, PublishesTheScenesToolsFromADeviceOnTcp) {
  const LoopbackListener listener;
  const std::string port = std::to_string(listener.port);
  std::unique_ptr<NdiDeviceServer> server;
  std::thread accepting([&] {
    const int accepted = listener.accept();
    if (accepted >= 0) server = std::make_unique<NdiDeviceServer>(accepted, SimulatedNdiDevice(device_tools()));
  });
  StationStandIn<dds::ToolPose, 1024> station(182);
  // The scene names another port; the flag names the device.
  ChildProcess device({kBin + "/navdevice", "ndi", "--scene", ndi_scene("    host: 127.0.0.1\n    port: 1\n"), "--tcp",
                       "127.0.0.1:" + port, "--seconds", "2", "--domain", "182"},
                      temporary_path("navdevice_ndi_tcp.log"));
  const auto received = run_device(device, station);
  accepting.join();
  expect_mapped_poses(received, device);
}

TEST(NavdeviceNdi, NamesTheDeviceThatIsMissing) {
  ChildProcess simulated({kBin + "/navdevice", "ndi", "--scene", example_scene_path("demo.yaml"), "--no-wait"},
                         temporary_path("navdevice_ndi_simulated.log"));
  EXPECT_EQ(simulated.wait(std::chrono::seconds(30)), 1);
  EXPECT_NE(simulated.log().find("devices.tracker is not an NDI tracker"), std::string::npos) << simulated.log();
  ChildProcess absent({kBin + "/navdevice", "ndi", "--scene", ndi_scene("    serial: /dev/no-such-tty\n"), "--no-wait"},
                      temporary_path("navdevice_ndi_absent.log"));
  EXPECT_EQ(absent.wait(std::chrono::seconds(30)), 1);
  EXPECT_NE(absent.log().find("navdevice ndi: "), std::string::npos) << absent.log();
  EXPECT_NE(absent.log().find("/dev/no-such-tty"), std::string::npos) << absent.log();
  ChildProcess usage({kBin + "/navdevice", "ndi", "--tcp", "nohost"}, temporary_path("navdevice_ndi_usage.log"));
  EXPECT_EQ(usage.wait(std::chrono::seconds(30)), 2);
}

}  // namespace
}  // namespace nav::testing
