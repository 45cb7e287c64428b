#pragma once
// The NDI combined API driver (Polaris / Aurora / Vega over serial or TCP): initialises the
// device and its port handles (INIT, PHSR 02 + PINIT, PHSR 03 + PENA), starts tracking,
// polls BX (binary) or TX (text) replies into tracker samples, stops (TSTOP).
// I/O-thread code.
#include <cstdint>
#include <vector>

#include "nav/trackers/ndi_connection.hpp"
#include "nav/trackers/ndi_protocol.hpp"
#include "nav/trackers/tracker_sample.hpp"

namespace nav::trackers::ndi {

/// Which tracking reply the driver polls.
enum class ReplyFormat { bx, tx };

/// An initialised NDI device with its enabled port handles.
class NdiTracker {
 public:
  /// Initialises the device on `connection` and enables every port handle as dynamic.
  static Result<NdiTracker> start(Connection connection);
  /// One tracking reply: a sample per enabled handle, tool_id = port handle, measured at
  /// `request_time_ns` (the station time the request was sent).
  Result<std::vector<TrackerSample>> poll(ReplyFormat format, TimeNs request_time_ns);
  /// Stops tracking (TSTOP).
  Status stop();
  const std::vector<std::uint8_t>& handles() const noexcept { return handles_; }

 private:
  explicit NdiTracker(Connection connection) : connection_(std::move(connection)) {}
  Connection connection_;
  std::vector<std::uint8_t> handles_;
};

/// The tracker sample of one handle record (positions from mm to m).
TrackerSample to_sample(const HandleRecord& record, TimeNs measured_time_ns);

}  // namespace nav::trackers::ndi
