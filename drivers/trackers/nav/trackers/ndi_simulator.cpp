#include "nav/trackers/ndi_simulator.hpp"

#include <fcntl.h>
#include <poll.h>
#include <stdlib.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstring>

namespace nav::trackers::ndi {
namespace {

constexpr const char* kOkay = "OKAY";
constexpr const char* kInvalidCommand = "ERROR01";
constexpr const char* kBadCrc = "ERROR04";
constexpr const char* kBadParameter = "ERROR0D";
constexpr const char* kNotTracking = "ERROR0C";

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
    command.crc_ok = std::sscanf(std::string(crc_text).c_str(), "%4X", &crc) == 1 &&
                     crc == crc16(line.substr(0, line.size() - 4));
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

SimulatedNdiDevice::SimulatedNdiDevice(std::vector<SimulatedNdiTool> tools, TimeNs frame_period_ns)
    : frame_period_ns_(frame_period_ns) {
  for (SimulatedNdiTool& tool : tools) ports_.push_back({tool, false, false});
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
      const std::uint16_t status = static_cast<std::uint16_t>(kPortOccupied | (port.initialized ? kPortInitialized : 0u) |
                                                              (port.enabled ? kPortEnabled : 0u));
      if (wanted) handles.push_back({port.tool.handle, status});
    }
    return frame_reply(encode_phsr(handles));
  }
  if (command.name == "PINIT" || command.name == "PENA") {
    const int handle = parse_handle(command.arguments);
    for (Port& port : ports_) {
      if (port.tool.handle != handle) continue;
      if (command.name == "PINIT") {
        port.initialized = true;
        return frame_reply(kOkay);
      }
      if (!port.initialized || command.arguments.size() != 3) return frame_reply(kBadParameter);
      port.enabled = true;
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

NdiDeviceServer::NdiDeviceServer(int fd, SimulatedNdiDevice device)
    : fd_(fd), device_(std::move(device)), thread_([this] { serve(); }) {}

NdiDeviceServer::~NdiDeviceServer() {
  stop_.store(true);
  thread_.join();
  ::close(fd_);
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
    return Error{std::string("cannot open a pseudo-terminal: ") + std::strerror(errno), "/dev/ptmx", 0, ""};
  }
  termios settings{};
  if (tcgetattr(master, &settings) == 0) {
    cfmakeraw(&settings);
    tcsetattr(master, TCSANOW, &settings);
  }
  char name[128];
  if (ptsname_r(master, name, sizeof name) != 0) {
    ::close(master);
    return Error{"ptsname failed", "/dev/ptmx", 0, ""};
  }
  return PseudoTerminal{master, name};
}

}  // namespace nav::trackers::ndi
