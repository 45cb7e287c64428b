#pragma once
// OpenIGTLink over TCP: a listener bound to one named address (loopback by default, never
// every interface, which OpenIGTLink's own server socket takes) and message streams that read
// one checked message at a time within a deadline. I/O-thread code: blocks in poll(), allocates.
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "nav/core/clock.hpp"
#include "nav/core/error.hpp"
#include "nav/igtl/igtl_wire.hpp"

namespace nav::igtl {

inline constexpr int kDefaultPort = 18944;  ///< OpenIGTLink's (Slicer's OpenIGTLinkIF, PlusServer)

/// An IPv4 address and a port: where a listener binds or which peer a stream connects to.
struct Endpoint {
  std::string host = "127.0.0.1";
  int port = kDefaultPort;
  std::string text() const { return host + ":" + std::to_string(port); }
};

/// One message: its checked header, its body (CRC checked) and where in it the content lies
/// (the whole body but for a v3 message's extended header and metadata).
struct Message {
  MessageHeader header;
  std::vector<std::uint8_t> body;
  ContentRange content_at;
  std::span<const std::uint8_t> content() const { return std::span(body).subspan(content_at.offset, content_at.bytes); }
};

/// A TCP connection carrying OpenIGTLink messages; owns its socket.
class MessageStream {
 public:
  /// Connects to `peer` (a numeric IPv4 address and a port) within `timeout_ns`.
  static Result<MessageStream> connect(const Endpoint& peer, TimeNs timeout_ns);
  MessageStream(int fd, std::string peer) : fd_(fd), peer_(std::move(peer)) {}
  MessageStream(MessageStream&& other) noexcept;
  MessageStream& operator=(MessageStream&& other) noexcept;
  MessageStream(const MessageStream&) = delete;
  MessageStream& operator=(const MessageStream&) = delete;
  ~MessageStream();

  /// The next message within `timeout_ns` (0: one that is there now); a message whose header
  /// came in time has at least 1 s more for its body. A body that fails its CRC, or a v3 body
  /// whose sizes do not add up (content_range), is an Error and the stream goes on at the next message; a header
  /// refused (parse_header), a peer that closed or a message cut short closes the stream (open() turns false): where
  /// the next message starts is not known then. Every Error names the peer in its `file`.
  Result<Message> read(TimeNs timeout_ns);
  /// Sends one packed message whole.
  Status write(std::span<const std::uint8_t> message);
  bool open() const noexcept { return fd_ >= 0; }
  /// Closes the connection (open() turns false).
  void close() noexcept;
  const std::string& peer() const noexcept { return peer_; }

 private:
  Status read_exact(std::uint8_t* out, std::size_t count, TimeNs deadline_ns);
  int fd_ = -1;
  std::string peer_;
};

/// A listening TCP socket bound to one address: 127.0.0.1 unless a station names the address
/// of the interface its displays are on; the wildcard address is refused.
class Listener {
 public:
  /// Binds and listens; port 0 takes a free port (port() tells which).
  static Result<Listener> listen(const Endpoint& local);
  Listener(Listener&& other) noexcept : fd_(other.fd_), port_(other.port_) { other.fd_ = -1; }
  Listener& operator=(Listener&&) = delete;
  Listener(const Listener&) = delete;
  Listener& operator=(const Listener&) = delete;
  ~Listener();

  /// The next client within `timeout_ns`, or an Error (none came).
  Result<MessageStream> accept(TimeNs timeout_ns);
  int port() const noexcept { return port_; }

 private:
  Listener(int fd, int port) : fd_(fd), port_(port) {}
  int fd_ = -1;
  int port_ = 0;
};

}  // namespace nav::igtl
