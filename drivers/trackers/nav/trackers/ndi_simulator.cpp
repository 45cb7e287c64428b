#include "nav/trackers/ndi_simulator.hpp"

#include <fcntl.h>
#include <poll.h>
#include <stdlib.h>
#include <termios.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>

#include "nav/trackers/ndi_connection.hpp"

namespace nav::trackers::ndi {
namespace {

constexpr const char* kOkay = "OKAY";
constexpr const char* kInvalidCommand = "ERROR01";
constexpr const char* kBadCrc = "ERROR04";
constexpr const char* kBadParameter = "ERROR0D";
constexpr const char* kNotTracking = "ERROR0C";
constexpr const char* kNoToolDefinition = "ERROR0E";  // PINIT of a port whose written definition is no tool's
constexpr std::uint8_t kFirstRequestedHandle = 0x0A;  // handles PHRQ gives out

/// The name, arguments and CRC of a command line "NAME:args<CRC>" or "NAME args".
struct CommandLine {
  std::string_view name;
  std::string_view arguments;
  bool crc_ok = true;
};

CommandLine split(std::string_view line) {
  const auto separator = line.find_first_of(": ");
  if (separator == std::string_view::npos) return {line, {}, true};
  CommandLine command{line.substr(0, separator), line.substr(separator + 1), true};
  if (line[separator] == ':') {  // CRC format: the last 4 characters are the CRC of the rest
    if (command.arguments.size() < 4) return {command.name, {}, false};
    const std::string_view crc_text = line.substr(line.size() - 4);
    unsigned crc = 0;
    command.crc_ok =
        std::sscanf(std::string(crc_text).c_str(), "%4X", &crc) == 1 && crc == crc16(line.substr(0, line.size() - 4));
    command.arguments.remove_suffix(4);
  }
  return command;
}

int parse_handle(std::string_view text) {
  if (text.size() < 2) return -1;
  unsigned handle = 0;
  return std::sscanf(std::string(text.substr(0, 2)).c_str(), "%2X", &handle) == 1 ? static_cast<int>(handle) : -1;
}

}  // namespace

SimulatedNdiDevice::SimulatedNdiDevice(std::vector<SimulatedNdiTool> tools, TimeNs frame_period_ns, int baud)
    : baud_(baud), frame_period_ns_(frame_period_ns) {
  for (SimulatedNdiTool& tool : tools) {
    if (tool.definition.empty())
      ports_.push_back({tool, false, false, {}});
    else
      passive_.push_back(tool);
  }
}

HandleRecord SimulatedNdiDevice::record(std::size_t index, std::uint32_t frame) const {
  const Port& port = ports_[index];
  HandleRecord record;
  record.handle = port.tool.handle;
  record.frame_number = frame;
  record.port_status = kPortOccupied | (port.initialized ? kPortInitialized : 0u) | (port.enabled ? kPortEnabled : 0u);
  if (!port.enabled) {
    record.state = ToolState::disabled;
    return record;
  }
  const bool missing = port.tool.missing_every != 0 && frame % port.tool.missing_every == 0;
  const bool partly_out = port.tool.partly_out_every != 0 && frame % port.tool.partly_out_every == 0;
  if (partly_out) record.port_status |= kPortPartlyOutOfVolume;
  record.state = state_from_bits(missing, false, record.port_status);
  if (missing) return record;
  std::array<double, 3> position_m{};
  port.tool.trajectory.at(static_cast<TimeNs>(frame) * frame_period_ns_, position_m, record.orientation_wxyz);
  for (int k = 0; k < 3; ++k) record.position_mm[k] = position_m[k] * 1e3;
  record.error_mm = port.tool.error_mm;
  return record;
}

std::string SimulatedNdiDevice::reply_tracking(std::string_view name, std::string_view options) {
  if (!tracking_) return frame_reply(kNotTracking);
  if (options != "0001" && !options.empty()) return frame_reply(kBadParameter);
  TrackingReply reply;
  for (std::size_t i = 0; i < ports_.size(); ++i) {
    if (ports_[i].enabled) reply.handles.push_back(record(i, frame_));
  }
  ++frame_;
  return name == "BX" ? encode_bx(reply) : frame_reply(encode_tx(reply));
}

std::string SimulatedNdiDevice::reply_port(std::string_view name, std::string_view arguments) {
  const int handle = parse_handle(arguments);
  for (Port& port : ports_) {
    if (port.tool.handle != handle) continue;
    if (name == "PINIT") {
      if (!port.written.empty()) {  // a requested port: its definition must be a passive tool's
        const auto tool = std::find_if(passive_.begin(), passive_.end(), [&](const SimulatedNdiTool& t) {
          return t.definition + std::string(kRomBytes - std::min(kRomBytes, t.definition.size()), '\0') == port.written;
        });
        if (tool == passive_.end()) return frame_reply(kNoToolDefinition);
        const std::uint8_t assigned = port.tool.handle;
        port.tool = *tool;
        port.tool.handle = assigned;
      }
      port.initialized = true;
      return frame_reply(kOkay);
    }
    if (!port.initialized || arguments.size() != 3) return frame_reply(kBadParameter);
    port.enabled = true;
    return frame_reply(kOkay);
  }
  return frame_reply(kBadParameter);
}

std::string SimulatedNdiDevice::respond(std::string_view line) {
  const CommandLine command = split(line);
  if (!command.crc_ok) return frame_reply(kBadCrc);
  if (command.name == "INIT") {
    tracking_ = false;
    return frame_reply(kOkay);
  }
  if (command.name == "PHSR") {
    // 00 all handles, 02 handles to initialise, 03 handles to enable.
    std::vector<PortHandle> handles;
    for (const Port& port : ports_) {
      const bool wanted = command.arguments == "02"   ? !port.initialized
                          : command.arguments == "03" ? port.initialized && !port.enabled
                                                      : true;
      const std::uint16_t status = static_cast<std::uint16_t>(
          kPortOccupied | (port.initialized ? kPortInitialized : 0u) | (port.enabled ? kPortEnabled : 0u));
      if (wanted) handles.push_back({port.tool.handle, status});
    }
    return frame_reply(encode_phsr(handles));
  }
  if (command.name == "PINIT" || command.name == "PENA") return reply_port(command.name, command.arguments);
  if (command.name == "COMM") {
    const std::optional<int> baud = comm_baud(command.arguments);
    if (!baud) return frame_reply(kBadParameter);
    baud_ = *baud;  // its OKAY goes out at the old rate; the next line must come at the new one
    return frame_reply(kOkay);
  }
  if (command.name == "PHRQ") {
    if (command.arguments != kPassiveToolRequest) return frame_reply(kBadParameter);
    std::uint8_t handle = kFirstRequestedHandle;
    for (const Port& port : ports_)
      handle = std::max<std::uint8_t>(handle, static_cast<std::uint8_t>(port.tool.handle + 1));
    SimulatedNdiTool requested;
    requested.handle = handle;
    ports_.push_back({requested, false, false, std::string(kRomBytes, '\0')});
    char reply[8];
    std::snprintf(reply, sizeof reply, "%02X", handle);
    return frame_reply(reply);
  }
  if (command.name == "PVWR") {
    const Result<RomWrite> write = decode_pvwr(command.arguments);
    if (!write) return frame_reply(kBadParameter);
    for (Port& port : ports_) {
      if (port.tool.handle != write.value().handle || port.written.empty()) continue;
      port.written.replace(write.value().address, kRomChunkBytes, write.value().bytes);
      return frame_reply(kOkay);
    }
    return frame_reply(kBadParameter);
  }
  if (command.name == "TSTART") {
    tracking_ = true;
    return frame_reply(kOkay);
  }
  if (command.name == "TSTOP") {
    tracking_ = false;
    return frame_reply(kOkay);
  }
  if (command.name == "BX" || command.name == "TX") return reply_tracking(command.name, command.arguments);
  return frame_reply(kInvalidCommand);
}

NdiDeviceServer::NdiDeviceServer(int fd, SimulatedNdiDevice device, const std::string& serial_path)
    : fd_(fd),
      serial_fd_(serial_path.empty() ? -1 : ::open(serial_path.c_str(), O_RDONLY | O_NOCTTY | O_CLOEXEC)),
      device_(std::move(device)),
      thread_([this] { serve(); }) {}

NdiDeviceServer::~NdiDeviceServer() {
  stop_.store(true);
  thread_.join();
  ::close(fd_);
  if (serial_fd_ >= 0) ::close(serial_fd_);
}

bool NdiDeviceServer::host_at_device_rate() const {
  termios settings{};
  if (serial_fd_ < 0 || tcgetattr(serial_fd_, &settings) != 0) return true;  // TCP, or no pty to look at
  return termios_speed(device_.baud()) == cfgetospeed(&settings);
}

void NdiDeviceServer::serve() {
  std::string line;
  while (!stop_.load()) {
    pollfd waiting{fd_, POLLIN, 0};
    if (::poll(&waiting, 1, 20) <= 0) continue;
    if ((waiting.revents & (POLLHUP | POLLERR)) && !(waiting.revents & POLLIN)) {
      std::this_thread::sleep_for(std::chrono::milliseconds(2));  // no reader on the other side yet
      continue;
    }
    char buffer[256];
    const ssize_t got = ::read(fd_, buffer, sizeof buffer);
    if (got <= 0) continue;
    for (ssize_t i = 0; i < got; ++i) {
      if (buffer[i] != '\r') {
        line += buffer[i];
        continue;
      }
      if (!host_at_device_rate()) {  // noise at the device's rate: no reply
        line.clear();
        garbled_.fetch_add(1);
        continue;
      }
      const std::string reply = device_.respond(line);
      line.clear();
      for (std::size_t sent = 0; sent < reply.size();) {
        const ssize_t written = ::write(fd_, reply.data() + sent, reply.size() - sent);
        if (written <= 0 && errno != EINTR && errno != EAGAIN) break;
        if (written > 0) sent += static_cast<std::size_t>(written);
      }
      commands_.fetch_add(1);
    }
  }
}

Result<PseudoTerminal> open_pseudo_terminal() {
  const int master = posix_openpt(O_RDWR | O_NOCTTY | O_CLOEXEC);
  if (master < 0 || grantpt(master) != 0 || unlockpt(master) != 0) {
    if (master >= 0) ::close(master);
    return Error{.message = std::string("cannot open a pseudo-terminal: ") + std::strerror(errno), .file = "/dev/ptmx"};
  }
  termios settings{};
  if (tcgetattr(master, &settings) == 0) {
    cfmakeraw(&settings);
    tcsetattr(master, TCSANOW, &settings);
  }
  char name[128];
  if (ptsname_r(master, name, sizeof name) != 0) {
    ::close(master);
    return Error{.message = "ptsname failed", .file = "/dev/ptmx"};
  }
  return PseudoTerminal{master, name};
}

}  // namespace nav::trackers::ndi
