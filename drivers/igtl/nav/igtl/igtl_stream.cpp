#include "nav/igtl/igtl_stream.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>

namespace nav::igtl {
namespace {

constexpr TimeNs kBodyTimeoutNs = kNsPerSecond;  // a body whose header came has this long at least

std::string errno_text(const char* what) { return std::string(what) + ": " + std::strerror(errno); }

/// The IPv4 socket address of `endpoint`, or an Error naming it (a host name is not taken:
/// the station names its peers by address).
Result<sockaddr_in> ipv4_address(const Endpoint& endpoint) {
  sockaddr_in address{};
  address.sin_family = AF_INET;
  if (endpoint.port < 0 || endpoint.port > 65535)
    return Error{.message = "a port from 0 to 65535", .file = endpoint.text(), .field = "port"};
  address.sin_port = htons(static_cast<std::uint16_t>(endpoint.port));
  if (::inet_pton(AF_INET, endpoint.host.c_str(), &address.sin_addr) != 1)
    return Error{.message = "not a numeric IPv4 address", .file = endpoint.text(), .field = "host"};
  return address;
}

/// Waits until `fd` is ready for `events` or `deadline_ns` passes; false on timeout. Looks at
/// least once, so a deadline already passed asks whether it is ready now.
bool wait_for(int fd, short events, TimeNs deadline_ns) {
  const MonotonicClock clock;
  for (;;) {
    const TimeNs left_ns = deadline_ns - clock.now_ns();
    pollfd waiting{fd, events, 0};
    const int ready = ::poll(&waiting, 1, left_ns <= 0 ? 0 : static_cast<int>(left_ns / kNsPerMs) + 1);
    if (ready > 0) return true;
    if ((ready < 0 && errno != EINTR) || left_ns <= 0) return false;
  }
}

}  // namespace

Result<MessageStream> MessageStream::connect(const Endpoint& peer, TimeNs timeout_ns) {
  const auto address = ipv4_address(peer);
  if (!address) return address.error();
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
  if (fd < 0) return Error{.message = errno_text("cannot open a socket"), .file = peer.text()};
  MessageStream stream(fd, peer.text());
  const auto* raw = reinterpret_cast<const sockaddr*>(&address.value());
  if (::connect(fd, raw, sizeof(sockaddr_in)) != 0 && errno != EINPROGRESS)
    return Error{.message = errno_text("cannot connect"), .file = peer.text()};
  if (!wait_for(fd, POLLOUT, MonotonicClock().now_ns() + timeout_ns))
    return Error{.message = "no connection within the timeout", .file = peer.text()};
  int failure = 0;
  socklen_t length = sizeof(failure);
  if (::getsockopt(fd, SOL_SOCKET, SO_ERROR, &failure, &length) != 0 || failure != 0)
    return Error{.message = std::string("cannot connect: ") + std::strerror(failure), .file = peer.text()};
  const int one = 1;
  ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof(one));  // poses go out at once
  return stream;
}

MessageStream::MessageStream(MessageStream&& other) noexcept : fd_(other.fd_), peer_(std::move(other.peer_)) {
  other.fd_ = -1;
}

MessageStream& MessageStream::operator=(MessageStream&& other) noexcept {
  if (this != &other) {
    close();
    fd_ = other.fd_;
    peer_ = std::move(other.peer_);
    other.fd_ = -1;
  }
  return *this;
}

MessageStream::~MessageStream() { close(); }

void MessageStream::close() noexcept {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

Status MessageStream::read_exact(std::uint8_t* out, std::size_t count, TimeNs deadline_ns) {
  while (count > 0) {
    if (!wait_for(fd_, POLLIN, deadline_ns)) return Error{.message = "no message within the timeout", .file = peer_};
    const ssize_t got = ::recv(fd_, out, count, 0);
    if (got < 0 && (errno == EINTR || errno == EAGAIN)) continue;
    if (got <= 0) {
      close();
      return Error{.message = got == 0 ? "the peer closed the connection" : errno_text("read failed"), .file = peer_};
    }
    out += got;
    count -= static_cast<std::size_t>(got);
  }
  return Done{};
}

Result<Message> MessageStream::read(TimeNs timeout_ns) {
  if (!open()) return Error{.message = "the connection is closed", .file = peer_};
  const TimeNs deadline_ns = MonotonicClock().now_ns() + timeout_ns;
  std::uint8_t header_bytes[kHeaderBytes];
  if (Status got = read_exact(header_bytes, kHeaderBytes, deadline_ns); !got) return got.error();
  auto header = parse_header(header_bytes);
  if (!header) {
    close();  // where the next message starts is not known
    return Error{
        .message = header.error().message + " (connection closed)", .file = peer_, .field = header.error().field};
  }
  Message message;
  message.body.resize(header.value().body_bytes);  // at most its type's limit
  message.header = std::move(header.value());
  const TimeNs body_deadline_ns = std::max(deadline_ns, MonotonicClock().now_ns() + kBodyTimeoutNs);
  if (Status got = read_exact(message.body.data(), message.body.size(), body_deadline_ns); !got) {
    close();  // cut short
    return got.error();
  }
  if (Status checked = check_body(message.header, message.body); !checked)
    return Error{.message = checked.error().message, .file = peer_, .field = checked.error().field};
  auto range = content_range(message.header, message.body);
  if (!range) return Error{.message = range.error().message, .file = peer_, .field = range.error().field};
  message.content_at = range.value();
  return message;
}

Status MessageStream::write(std::span<const std::uint8_t> message) {
  if (!open()) return Error{.message = "the connection is closed", .file = peer_};
  const TimeNs deadline_ns = MonotonicClock().now_ns() + kNsPerSecond;
  while (!message.empty()) {
    if (!wait_for(fd_, POLLOUT, deadline_ns)) return Error{.message = "the peer takes nothing for 1 s", .file = peer_};
    const ssize_t sent = ::send(fd_, message.data(), message.size(), MSG_NOSIGNAL);
    if (sent < 0 && (errno == EINTR || errno == EAGAIN)) continue;
    if (sent <= 0) {
      close();
      return Error{.message = errno_text("write failed"), .file = peer_};
    }
    message = message.subspan(static_cast<std::size_t>(sent));
  }
  return Done{};
}

Result<Listener> Listener::listen(const Endpoint& local) {
  const auto address = ipv4_address(local);
  if (!address) return address.error();
  if (address.value().sin_addr.s_addr == htonl(INADDR_ANY))
    return Error{.message = "the bridge listens on one named address, not on every interface",
                 .file = local.text(),
                 .field = "host"};
  const int fd = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC | SOCK_NONBLOCK, 0);
  if (fd < 0) return Error{.message = errno_text("cannot open a socket"), .file = local.text()};
  const int one = 1;
  ::setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof(one));
  Listener listener(fd, local.port);
  if (::bind(fd, reinterpret_cast<const sockaddr*>(&address.value()), sizeof(sockaddr_in)) != 0 || ::listen(fd, 4) != 0)
    return Error{.message = errno_text("cannot listen"), .file = local.text()};
  sockaddr_in bound{};
  socklen_t length = sizeof(bound);
  if (::getsockname(fd, reinterpret_cast<sockaddr*>(&bound), &length) == 0) listener.port_ = ntohs(bound.sin_port);
  return listener;
}

Listener::~Listener() {
  if (fd_ >= 0) ::close(fd_);
}

Result<MessageStream> Listener::accept(TimeNs timeout_ns) {
  const std::string local = "port " + std::to_string(port_);
  if (!wait_for(fd_, POLLIN, MonotonicClock().now_ns() + timeout_ns))
    return Error{.message = "no client within the timeout", .file = local};
  sockaddr_in peer{};
  socklen_t length = sizeof(peer);
  const int fd = ::accept4(fd_, reinterpret_cast<sockaddr*>(&peer), &length, SOCK_CLOEXEC | SOCK_NONBLOCK);
  if (fd < 0) return Error{.message = errno_text("accept failed"), .file = local};
  char host[INET_ADDRSTRLEN] = {};
  ::inet_ntop(AF_INET, &peer.sin_addr, host, sizeof(host));
  const int one = 1;
  ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof(one));
  return MessageStream(fd, std::string(host) + ":" + std::to_string(ntohs(peer.sin_port)));
}

}  // namespace nav::igtl
