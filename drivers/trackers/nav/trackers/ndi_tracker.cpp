#include "nav/trackers/ndi_tracker.hpp"

#include <cstdio>

namespace nav::trackers::ndi {
namespace {

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

Result<NdiTracker> NdiTracker::start(Connection connection) {
  NdiTracker tracker(std::move(connection));
  Result<std::string> init = tracker.connection_.command("INIT", "");
  if (!init) return init.error();
  if (Status initialised = for_listed_handles(tracker.connection_, "02", "PINIT", "", nullptr); !initialised) {
    return initialised.error();
  }
  if (Status enabled = for_listed_handles(tracker.connection_, "03", "PENA", "D", &tracker.handles_); !enabled) {
    return enabled.error();
  }
  if (tracker.handles_.empty()) return Error{"the device reports no port handle to enable", "", 0, "PHSR"};
  Result<std::string> started = tracker.connection_.command("TSTART", "");
  if (!started) return started.error();
  return tracker;
}

Result<std::vector<TrackerSample>> NdiTracker::poll(ReplyFormat format, TimeNs request_time_ns) {
  Result<TrackingReply> reply = Error{"", "", 0, ""};
  if (format == ReplyFormat::bx) {
    Result<std::string> bytes = connection_.binary_command("BX", "0001");
    if (!bytes) return bytes.error();
    reply = decode_bx(bytes.value());
  } else {
    Result<std::string> body = connection_.command("TX", "0001");
    if (!body) return body.error();
    reply = decode_tx(body.value());
  }
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
