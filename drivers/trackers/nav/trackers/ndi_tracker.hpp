#pragma once
// The NDI combined API driver (Polaris / Aurora / Vega over serial or TCP): on a serial line
// negotiates the rate (INIT at 9600, a serial break and its RESET when the device does not
// answer, COMM), loads passive tools' definitions (PHRQ, PVWR), initialises the device and its
// port handles (INIT, PHSR 02 + PINIT, PHSR 03 + PENA), starts tracking, polls BX (binary) or
// TX (text) replies into tracker samples, stops (TSTOP). I/O-thread code.
#include <cstdint>
#include <vector>

#include "nav/trackers/ndi_connection.hpp"
#include "nav/trackers/ndi_protocol.hpp"
#include "nav/trackers/tracker_sample.hpp"

namespace nav::trackers::ndi {

/// Which tracking reply the driver polls.
enum class ReplyFormat { bx, tx };

/// Brings a serial link to `baud` (one of kSerialBauds) as ndicapi does: INIT at 9600 8N1;
/// without an answer, a serial break, whose RESET reply says the device is back at 9600, and
/// INIT again; then COMM, and the host follows after the device's OKAY. Errors name the line.
Status negotiate_serial(Connection& connection, int baud);

/// A passive tool's definition: its .rom file, at most 1024 bytes; an error names the file.
Result<std::string> read_tool_definition(const std::string& path);

/// An initialised NDI device with its enabled port handles.
class NdiTracker {
 public:
  /// Initialises the device on `connection`, loads the passive tools' `definitions` (a port
  /// handle for each, PHRQ, then PVWR in 64-byte chunks) and enables every port handle as dynamic.
  static Result<NdiTracker> start(Connection connection, const std::vector<std::string>& definitions = {});
  /// One tracking reply: a sample per enabled handle, tool_id = port handle, measured at
  /// `request_time_ns` (the station time the request was sent).
  Result<std::vector<TrackerSample>> poll(ReplyFormat format, TimeNs request_time_ns);
  /// Stops tracking (TSTOP).
  Status stop();
  const std::vector<std::uint8_t>& handles() const noexcept { return handles_; }
  /// The port handle the device gave each passive tool, in the order of their definitions.
  const std::vector<std::uint8_t>& passive_handles() const noexcept { return passive_handles_; }

 private:
  explicit NdiTracker(Connection connection) : connection_(std::move(connection)) {}
  Connection connection_;
  std::vector<std::uint8_t> handles_, passive_handles_;
};

/// The tracker sample of one handle record (positions from mm to m).
TrackerSample to_sample(const HandleRecord& record, TimeNs measured_time_ns);

}  // namespace nav::trackers::ndi
