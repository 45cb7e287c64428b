#pragma once
// The OpenIGTLink bridge of a scene (navbridge igtl): in, a PlusServer's tools and images as
// the station's device samples on DDS (a devices participant); out, the station's outputs to
// every display connected to the bridge (a display participant), 3D Slicer's OpenIGTLinkIF
// among them. Both sides listen or connect only where the scene names (loopback by default).
// A message refused is counted, printed with its sender and field, and the bridge goes on; a
// PlusServer lost is reconnected; a display that takes nothing for 1 s is dropped. I/O code:
// threads, sockets, allocation.
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>

#include "nav/core/error.hpp"
#include "nav/dds/topics.hpp"
#include "nav/station/scene.hpp"

namespace nav::bridge {

/// What the bridge did so far.
struct BridgeTotals {
  std::uint64_t poses_in = 0;          ///< TRANSFORMs and TDATA elements published as tool poses
  std::uint64_t frames_in = 0;         ///< IMAGEs published as ultrasound frames
  std::uint64_t skipped_in = 0;        ///< other types, or names the scene does not map (messages, TDATA elements)
  std::uint64_t refused_in = 0;        ///< messages (or TDATA elements) refused: header, size, CRC, a field
  std::uint64_t plus_connections = 0;  ///< connections to (or from) the PlusServer
  std::uint64_t messages_out = 0;      ///< messages sent, summed over displays
  std::uint64_t displays_connected = 0;
  std::uint64_t displays_dropped = 0;  ///< displays closed or too slow
  std::uint64_t refused_out = 0;       ///< station samples that could not be sent (another scene's surface)
  std::uint64_t images_unplaced = 0;   ///< ultrasound frames not sent: no registration or probe pose at their time
};

/// A running bridge's settings beyond the scene's.
struct BridgeOptions {
  /// Where the bridge's own messages go, a line each, from either side's thread (default: stderr,
  /// "navbridge igtl: ...").
  std::function<void(const std::string&)> log;
  double display_rate_hz = 30.0;  ///< the most updates a second each display gets
};

/// The bridge of one scene.
class IgtlBridge {
 public:
  /// Builds what `scene` (with an openigtlink section) declares: its liver's surface, the two
  /// participants, the displays' listener, and the PlusServer's when it connects to the bridge.
  /// Init-time; an Error names the scene's field or the address at fault.
  static Result<std::unique_ptr<IgtlBridge>> open(const station::Scene& scene, BridgeOptions options = {});
  ~IgtlBridge();
  IgtlBridge(const IgtlBridge&) = delete;
  IgtlBridge& operator=(const IgtlBridge&) = delete;

  /// Runs the inbound side on a thread of its own and the outbound side on the caller's until
  /// stop(); then joins.
  void run();
  /// Asks run() to return (any thread).
  void stop() noexcept { stopping_.store(true); }
  BridgeTotals totals() const noexcept;
  /// The port displays connect to (the scene's, or the one taken for port 0).
  int displays_port() const noexcept;
  /// The port a PlusServer connects to when the bridge listens for it; 0 otherwise.
  int plus_port() const noexcept;
  /// The readers its writer of `topic` (poses or frames) has matched: the station's among them
  /// once DDS discovery has run both ways.
  std::size_t readers_matched(dds::Topic topic) const;

 private:
  struct Impl;
  explicit IgtlBridge(std::unique_ptr<Impl> impl);
  void run_inbound();
  void run_outbound();
  std::unique_ptr<Impl> impl_;
  std::atomic<bool> stopping_{false};
};

}  // namespace nav::bridge
