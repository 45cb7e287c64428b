#pragma once
// The byte link to an NDI device: a serial port (a real one or a pseudo-terminal) or a TCP
// socket, sending framed commands and reading text or BX replies with a timeout.
// I/O-thread code: it blocks in poll() up to the timeout and allocates.
#include <optional>
#include <string>
#include <string_view>

#include <termios.h>

#include "nav/core/clock.hpp"
#include "nav/core/error.hpp"

namespace nav::trackers::ndi {

/// The termios speed of a serial rate of kSerialBauds, or nothing.
std::optional<speed_t> termios_speed(int baud);

/// An open link to an NDI device; owns its file descriptor.
class Connection {
 public:
  /// Opens a serial device (e.g. /dev/ttyUSB0 or a pty slave) raw, 8N1, at the rate of a
  /// device after reset (9600; negotiate_serial raises it).
  static Result<Connection> open_serial(const std::string& path);
  /// Connects to host:port (NDI Vega / Polaris over Ethernet).
  static Result<Connection> open_tcp(const std::string& host, int port);
  /// Adopts an already open descriptor.
  explicit Connection(int fd) : fd_(fd) {}
  Connection(Connection&& other) noexcept : fd_(other.fd_), path_(std::move(other.path_)) { other.fd_ = -1; }
  Connection& operator=(Connection&& other) noexcept;
  Connection(const Connection&) = delete;
  Connection& operator=(const Connection&) = delete;
  ~Connection();

  /// Sends NAME:args with CRC and returns the CRC-checked text reply body. "ERRORnn"
  /// replies become errors naming the command.
  Result<std::string> command(std::string_view name, std::string_view arguments);
  /// Sends a BX command and returns the raw BX reply (checked by decode_bx).
  Result<std::string> binary_command(std::string_view name, std::string_view arguments);

  /// Reads one CRC-checked text reply the device sends unasked (RESET after a break).
  Result<std::string> read_reply() { return read_text_line(""); }

  /// Serial links only: sets the host's rate (one of kSerialBauds).
  Status set_serial_speed(int baud);
  /// Serial links only: sends a serial break (a device resets to 9600 and replies RESET).
  Status send_break();
  /// Drops whatever was received and not read.
  void discard_input();
  /// The serial device's path ("" for TCP), for errors.
  const std::string& path() const noexcept { return path_; }

  /// How long a reply may take before it is an error.
  TimeNs reply_timeout_ns = 2 * kNsPerSecond;

 private:
  Status send(std::string_view bytes);
  Result<std::string> read_exact(std::size_t count);
  Result<std::string> read_text_line(std::string prefix);
  int fd_ = -1;
  std::string path_;  ///< a serial device's
};

}  // namespace nav::trackers::ndi
