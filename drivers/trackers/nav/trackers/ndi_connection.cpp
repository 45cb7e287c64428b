#include "nav/trackers/ndi_connection.hpp"

#include <fcntl.h>
#include <netdb.h>
#include <poll.h>
#include <sys/socket.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <optional>

#include "nav/trackers/ndi_protocol.hpp"

namespace nav::trackers::ndi {

Result<Connection> Connection::open_serial(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDWR | O_NOCTTY | O_CLOEXEC);
  if (fd < 0)
    return Error{.message = std::string("cannot open the serial device: ") + std::strerror(errno), .file = path};
  Connection connection(fd);
  connection.path_ = path;
  termios settings{};
  if (tcgetattr(fd, &settings) != 0)
    return Error{.message = std::string("not a serial device: ") + std::strerror(errno), .file = path};
  cfmakeraw(&settings);
  settings.c_cflag |= CLOCAL | CREAD;
  if (tcsetattr(fd, TCSANOW, &settings) != 0)
    return Error{.message = std::string("cannot set the serial line raw: ") + std::strerror(errno), .file = path};
  if (Status reset_rate = connection.set_serial_speed(kResetBaud); !reset_rate) return reset_rate.error();
  return connection;
}

std::optional<speed_t> termios_speed(int baud) {
  switch (baud) {
    case 9600:
      return B9600;
    case 19200:
      return B19200;
    case 38400:
      return B38400;
    case 57600:
      return B57600;
    case 115200:
      return B115200;
    case 230400:
      return B230400;
    case 921600:
      return B921600;
    default:
      return std::nullopt;
  }
}

Status Connection::set_serial_speed(int baud) {
  const std::optional<speed_t> speed = termios_speed(baud);
  if (!speed)
    return Error{.message = "no serial rate " + std::to_string(baud) + " on this host", .file = path_, .field = "COMM"};
  termios settings{};
  if (tcgetattr(fd_, &settings) != 0 || cfsetspeed(&settings, *speed) != 0 || tcsetattr(fd_, TCSADRAIN, &settings) != 0)
    return Error{
        .message = std::string("cannot set the serial rate: ") + std::strerror(errno), .file = path_, .field = "COMM"};
  return Done{};
}

Status Connection::send_break() {
  if (tcsendbreak(fd_, 0) != 0)
    return Error{.message = std::string("cannot send a serial break: ") + std::strerror(errno), .file = path_};
  return Done{};
}

void Connection::discard_input() {
  if (tcflush(fd_, TCIFLUSH) == 0) return;
  char buffer[256];  // not a terminal (TCP): read what is there
  for (pollfd waiting{fd_, POLLIN, 0}; ::poll(&waiting, 1, 0) > 0 && ::read(fd_, buffer, sizeof buffer) > 0;)
    waiting.revents = 0;
}

Result<Connection> Connection::open_tcp(const std::string& host, int port) {
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  addrinfo* found = nullptr;
  const std::string service = std::to_string(port);
  if (getaddrinfo(host.c_str(), service.c_str(), &hints, &found) != 0 || found == nullptr) {
    return Error{.message = "cannot resolve the NDI host", .file = host + ":" + service};
  }
  const int fd = ::socket(found->ai_family, found->ai_socktype | SOCK_CLOEXEC, found->ai_protocol);
  const bool connected = fd >= 0 && ::connect(fd, found->ai_addr, found->ai_addrlen) == 0;
  const int saved_errno = errno;
  freeaddrinfo(found);
  if (!connected) {
    if (fd >= 0) ::close(fd);
    return Error{.message = std::string("cannot connect: ") + std::strerror(saved_errno), .file = host + ":" + service};
  }
  return Connection(fd);
}

Connection& Connection::operator=(Connection&& other) noexcept {
  if (this != &other) {
    if (fd_ >= 0) ::close(fd_);
    fd_ = other.fd_;
    path_ = std::move(other.path_);
    other.fd_ = -1;
  }
  return *this;
}

Connection::~Connection() {
  if (fd_ >= 0) ::close(fd_);
}

Status Connection::send(std::string_view bytes) {
  while (!bytes.empty()) {
    const ssize_t written = ::write(fd_, bytes.data(), bytes.size());
    if (written < 0 && errno == EINTR) continue;
    if (written <= 0) return Error{.message = std::string("write to the NDI device failed: ") + std::strerror(errno)};
    bytes.remove_prefix(static_cast<std::size_t>(written));
  }
  return Done{};
}

Result<std::string> Connection::read_exact(std::size_t count) {
  std::string bytes;
  const MonotonicClock clock;
  const TimeNs deadline_ns = clock.now_ns() + reply_timeout_ns;
  while (bytes.size() < count) {
    const TimeNs left_ns = deadline_ns - clock.now_ns();
    pollfd waiting{fd_, POLLIN, 0};
    if (left_ns <= 0 || ::poll(&waiting, 1, static_cast<int>(left_ns / kNsPerMs) + 1) <= 0) {
      return Error{.message = "no reply from the NDI device within the timeout"};
    }
    char buffer[512];
    const ssize_t got = ::read(fd_, buffer, std::min(sizeof buffer, count - bytes.size()));
    if (got < 0 && errno == EINTR) continue;
    if (got <= 0) return Error{.message = "the NDI device closed the link"};
    bytes.append(buffer, static_cast<std::size_t>(got));
  }
  return bytes;
}

Result<std::string> Connection::read_text_line(std::string line) {
  while (line.empty() || line.back() != '\r') {
    Result<std::string> byte = read_exact(1);
    if (!byte) return byte.error();
    line += byte.value();
  }
  line.pop_back();
  return check_reply(line);
}

Result<std::string> Connection::command(std::string_view name, std::string_view arguments) {
  if (Status sent = send(frame_command(name, arguments)); !sent) return sent.error();
  Result<std::string> reply = read_text_line("");
  if (!reply) return Error{.message = reply.error().message, .field = std::string(name)};
  if (reply.value().rfind("ERROR", 0) == 0)
    return Error{.message = "device replied " + reply.value(), .field = std::string(name)};
  return reply;
}

Result<std::string> Connection::binary_command(std::string_view name, std::string_view arguments) {
  if (Status sent = send(frame_command(name, arguments)); !sent) return sent.error();
  Result<std::string> header = read_exact(6);
  if (!header) return Error{.message = header.error().message, .field = std::string(name)};
  const auto size = bx_reply_size(header.value());
  if (!size) {  // a text reply instead (an error): read the rest of the line
    Result<std::string> text = read_text_line(header.value());
    return Error{.message = text ? "device replied " + text.value() : text.error().message, .field = std::string(name)};
  }
  Result<std::string> rest = read_exact(*size - 6);
  if (!rest) return Error{.message = rest.error().message, .field = std::string(name)};
  return header.value() + rest.value();
}

}  // namespace nav::trackers::ndi
