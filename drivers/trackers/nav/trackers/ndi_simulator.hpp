#pragma once
// A simulated NDI device speaking the combined API over a file descriptor (the master side of
// a pseudo-terminal, or a TCP socket): INIT, COMM, PHRQ, PVWR, PHSR, PINIT, PENA, TSTART, BX,
// TX, TSTOP, with CRC-checked commands and replies, port handles, passive tools that appear
// when their definition is written, and tools that go missing or partly out of the volume on a
// schedule. On a pseudo-terminal it hears only a host at its own serial rate (9600 after
// power-on, then what COMM set); a serial break cannot cross a pseudo-terminal, so it never
// resets. For tests and demos of the NDI driver; not a real-time component.
#include <atomic>
#include <cstdint>
#include <string>
#include <string_view>
#include <thread>
#include <vector>

#include "nav/core/error.hpp"
#include "nav/trackers/ndi_protocol.hpp"
#include "nav/trackers/trajectory.hpp"

namespace nav::trackers::ndi {

/// One tool plugged into the simulated device.
struct SimulatedNdiTool {
  std::uint8_t handle = 1;
  Trajectory trajectory;
  std::uint32_t missing_every = 0;     // every n-th frame missing (0: never)
  std::uint32_t partly_out_every = 0;  // every n-th frame partly out of volume (0: never)
  double error_mm = 0.12;              // reported fit error
  std::string definition;  // a passive tool's .rom bytes: it appears when they are written (PHRQ, PVWR); empty: active
};

/// The device's state machine, independent of the link (testable on strings).
class SimulatedNdiDevice {
 public:
  explicit SimulatedNdiDevice(std::vector<SimulatedNdiTool> tools, TimeNs frame_period_ns = kNsPerSecond / 60,
                              int baud = kResetBaud);
  /// The reply bytes to one command line (without its CR): framed text or a BX reply.
  std::string respond(std::string_view line);
  /// The record of tool `index` at `frame` as the device would report it.
  HandleRecord record(std::size_t index, std::uint32_t frame) const;
  std::uint32_t frame_number() const noexcept { return frame_; }
  /// The serial rate it listens and replies at.
  int baud() const noexcept { return baud_; }

 private:
  std::string reply_tracking(std::string_view name, std::string_view options);
  std::string reply_port(std::string_view name, std::string_view arguments);
  struct Port {
    SimulatedNdiTool tool;
    bool initialized = false;
    bool enabled = false;
    std::string written;  ///< a requested port's definition as written so far (kRomBytes)
  };
  std::vector<Port> ports_;
  std::vector<SimulatedNdiTool> passive_;  ///< tools that appear when their definition is written
  int baud_ = kResetBaud;
  TimeNs frame_period_ns_;
  bool tracking_ = false;
  std::uint32_t frame_ = 0;
};

/// Serves a SimulatedNdiDevice on a descriptor from a thread until destroyed.
class NdiDeviceServer {
 public:
  /// Takes ownership of `fd` (e.g. a pty master) and starts serving. With the pty's
  /// `serial_path`, it hears a line only when the host's rate there is the device's.
  NdiDeviceServer(int fd, SimulatedNdiDevice device, const std::string& serial_path = "");
  ~NdiDeviceServer();
  NdiDeviceServer(const NdiDeviceServer&) = delete;
  NdiDeviceServer& operator=(const NdiDeviceServer&) = delete;
  /// Commands answered so far.
  std::uint64_t commands() const noexcept { return commands_.load(); }
  /// Lines the device could not hear: sent at another rate than its own.
  std::uint64_t garbled_lines() const noexcept { return garbled_.load(); }

 private:
  void serve();
  bool host_at_device_rate() const;
  int fd_;
  int serial_fd_ = -1;  ///< the pty's slave, for its rate
  SimulatedNdiDevice device_;
  std::atomic<bool> stop_{false};
  std::atomic<std::uint64_t> commands_{0}, garbled_{0};
  std::thread thread_;
};

/// A pseudo-terminal pair: the master for the simulated device, the slave's path for the
/// driver (as if it were /dev/ttyUSB0).
struct PseudoTerminal {
  int master_fd = -1;
  std::string slave_path;
};
/// Opens a raw pseudo-terminal (posix_openpt, grantpt, unlockpt).
Result<PseudoTerminal> open_pseudo_terminal();

}  // namespace nav::trackers::ndi
