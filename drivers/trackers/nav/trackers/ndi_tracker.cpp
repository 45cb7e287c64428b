#include "nav/trackers/ndi_tracker.hpp"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <thread>

namespace nav::trackers::ndi {
namespace {

constexpr TimeNs kInitProbeNs =
    200 * kNsPerMs;  // INIT's answer at 9600 when the device is there (ndicapi waits 100 ms)

std::string hex2(std::uint8_t value) {
  char text[4];
  std::snprintf(text, sizeof text, "%02X", value);
  return text;
}

/// Runs PHSR `option` and calls `command` (PINIT hh or PENA hhD) on each handle listed.
Status for_listed_handles(Connection& connection, const char* option, const char* command, const char* suffix,
                          std::vector<std::uint8_t>* collected) {
  Result<std::string> listed = connection.command("PHSR", option);
  if (!listed) return listed.error();
  Result<std::vector<PortHandle>> handles = decode_phsr(listed.value());
  if (!handles) return handles.error();
  for (const PortHandle& handle : handles.value()) {
    Result<std::string> done = connection.command(command, hex2(handle.handle) + suffix);
    if (!done) return done.error();
    if (collected != nullptr) collected->push_back(handle.handle);
  }
  return Done{};
}

}  // namespace

TrackerSample to_sample(const HandleRecord& record, TimeNs measured_time_ns) {
  TrackerSample sample;
  sample.tool_id = record.handle;
  sample.measured_time_ns = measured_time_ns;
  sample.state = record.state;
  sample.frame_number = record.frame_number;
  if (has_pose(record.state)) {
    for (int k = 0; k < 3; ++k) sample.position_m[k] = record.position_mm[k] * 1e-3;
    sample.orientation_wxyz = record.orientation_wxyz;
    sample.rms_error_m = record.error_mm * 1e-3;
  }
  return sample;
}

Status negotiate_serial(Connection& connection, int baud) {
  const std::optional<std::string> comm = comm_arguments(baud);
  if (!comm)
    return Error{.message = "no serial rate " + std::to_string(baud) + " the device and this host share",
                 .file = connection.path(),
                 .field = "COMM"};
  if (Status reset_rate = connection.set_serial_speed(kResetBaud); !reset_rate) return reset_rate;
  connection.discard_input();
  const TimeNs reply_timeout_ns = connection.reply_timeout_ns;
  connection.reply_timeout_ns = kInitProbeNs;
  const bool answered = connection.command("INIT", "").ok();
  connection.reply_timeout_ns = reply_timeout_ns;
  if (!answered) {  // at another rate, or busy: a break resets it to 9600
    connection.discard_input();
    if (Status broke = connection.send_break(); !broke) return broke;
    Result<std::string> reset = connection.read_reply();
    if (!reset || reset.value() != "RESET")
      return Error{.message = "no reply to INIT at 9600 8N1, and no RESET after a serial break" +
                              (reset ? ": the device said " + reset.value() : std::string()) +
                              " (is the device on, and is this its port?)",
                   .file = connection.path(),
                   .field = "INIT"};
    Result<std::string> init = connection.command("INIT", "");
    if (!init) return init.error();
  }
  Result<std::string> switched = connection.command("COMM", *comm);
  if (!switched) return switched.error();
  std::this_thread::sleep_for(std::chrono::milliseconds(100));  // the device changes its rate after its reply
  return connection.set_serial_speed(baud);
}

Result<std::string> read_tool_definition(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) return Error{.message = "cannot open the tool definition", .file = path};
  std::string bytes(kRomBytes + 1, '\0');  // one byte more than a device takes: never a whole large file
  file.read(bytes.data(), static_cast<std::streamsize>(bytes.size()));
  bytes.resize(static_cast<std::size_t>(file.gcount()));
  if (bytes.empty()) return Error{.message = "the tool definition is empty", .file = path};
  if (bytes.size() > kRomBytes) {
    std::error_code error;
    const std::uintmax_t size = std::filesystem::file_size(path, error);
    return Error{.message = "the tool definition has " +
                            (error ? std::string("more than 1024") : std::to_string(size)) +
                            " bytes; a device takes at most 1024",
                 .file = path};
  }
  return bytes;
}

namespace {

/// A port handle for a passive tool (PHRQ), its definition written into it (PVWR).
Result<std::uint8_t> load_passive_tool(Connection& connection, const std::string& definition) {
  Result<std::string> requested = connection.command("PHRQ", kPassiveToolRequest);
  if (!requested) return requested.error();
  unsigned handle = 0;
  if (requested.value().size() < 2 || std::sscanf(requested.value().substr(0, 2).c_str(), "%2X", &handle) != 1)
    return Error{.message = "PHRQ replied '" + requested.value() + "', not a port handle", .field = "PHRQ"};
  for (std::size_t address = 0; address < definition.size(); address += kRomChunkBytes) {
    const RomWrite chunk{static_cast<std::uint8_t>(handle), address, definition.substr(address, kRomChunkBytes)};
    Result<std::string> written = connection.command("PVWR", encode_pvwr(chunk));
    if (!written) return written.error();
  }
  return static_cast<std::uint8_t>(handle);
}

}  // namespace

Result<NdiTracker> NdiTracker::start(Connection connection, const std::vector<std::string>& definitions) {
  NdiTracker tracker(std::move(connection));
  Result<std::string> init = tracker.connection_.command("INIT", "");
  if (!init) return init.error();
  for (const std::string& definition : definitions) {
    Result<std::uint8_t> handle = load_passive_tool(tracker.connection_, definition);
    if (!handle) return handle.error();
    tracker.passive_handles_.push_back(handle.value());
  }
  if (Status initialised = for_listed_handles(tracker.connection_, "02", "PINIT", "", nullptr); !initialised) {
    return initialised.error();
  }
  if (Status enabled = for_listed_handles(tracker.connection_, "03", "PENA", "D", &tracker.handles_); !enabled) {
    return enabled.error();
  }
  if (tracker.handles_.empty()) return Error{.message = "the device reports no port handle to enable", .field = "PHSR"};
  Result<std::string> started = tracker.connection_.command("TSTART", "");
  if (!started) return started.error();
  return tracker;
}

namespace {

/// One BX (binary) tracking reply, decoded.
Result<TrackingReply> read_bx(Connection& connection) {
  Result<std::string> bytes = connection.binary_command("BX", "0001");
  if (!bytes) return bytes.error();
  return decode_bx(bytes.value());
}

/// One TX (text) tracking reply, decoded.
Result<TrackingReply> read_tx(Connection& connection) {
  Result<std::string> body = connection.command("TX", "0001");
  if (!body) return body.error();
  return decode_tx(body.value());
}

}  // namespace

Result<std::vector<TrackerSample>> NdiTracker::poll(ReplyFormat format, TimeNs request_time_ns) {
  Result<TrackingReply> reply = format == ReplyFormat::bx ? read_bx(connection_) : read_tx(connection_);
  if (!reply) return reply.error();
  std::vector<TrackerSample> samples;
  for (const HandleRecord& record : reply.value().handles) samples.push_back(to_sample(record, request_time_ns));
  return samples;
}

Status NdiTracker::stop() {
  Result<std::string> stopped = connection_.command("TSTOP", "");
  if (!stopped) return stopped.error();
  return Done{};
}

}  // namespace nav::trackers::ndi
