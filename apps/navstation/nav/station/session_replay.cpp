#include "nav/station/session_replay.hpp"

#include <algorithm>
#include <cstdio>
#include <memory>
#include <vector>

#include "nav/dds/pose_inbox.hpp"
#include "nav/dds/recording_file.hpp"
#include "nav/dds/sample_boundary.hpp"
#include "nav/dds/sample_codec.hpp"
#include "nav/station/station_dds.hpp"
#include "nav/station/station_loop.hpp"
#include "nav/station/station_session.hpp"

namespace nav::station {

namespace {

/// A recorded pose or frame, in arrival order (frames by their index in `frames`).
struct Arrival {
  TimeNs received_ns = 0;
  std::size_t record = 0;
};

/// Reads the recording's poses and frames into loop samples on the recording's own clock
/// (loop time 0 at the first arrival), each frame observed for its tumour point.
Result<std::vector<DeviceSample>> observed_session(dds::RecordingReader& reader, const ProbeImaging& imaging,
                                                   const DdsRunOptions& boundary, SessionReplay& out) {
  const ToolIds& tools = boundary.tools;
  const TimeNs device_to_host_ns = boundary.arrival.source_clock_offset_ns;
  std::vector<Arrival> arrivals;
  for (std::size_t i = 0; i < reader.record_count(); ++i) {
    auto record = reader.read(i);
    if (!record.ok()) {
      ++out.records_refused;
      continue;
    }
    const dds::Topic topic = record.value().topic;
    if (topic == dds::Topic::tool_pose || topic == dds::Topic::ultrasound_frame)
      arrivals.push_back({record.value().receive_time_ns, i});
  }
  std::stable_sort(arrivals.begin(), arrivals.end(),
                   [](const Arrival& a, const Arrival& b) { return a.received_ns < b.received_ns; });
  std::vector<DeviceSample> samples;
  if (arrivals.empty()) return samples;
  const TimeNs origin_ns = arrivals.front().received_ns;
  out.duration_ns = arrivals.back().received_ns - origin_ns;
  TumourObserver observer(imaging);
  auto frame = std::make_unique<dds::UltrasoundFrame>();
  dds::ToolPose pose;
  // The live station's boundary, with each record's arrival as its arrival.
  dds::SampleBoundary<dds::ToolPose> pose_boundary(boundary.arrival);
  dds::SampleBoundary<dds::UltrasoundFrame> frame_boundary(boundary.arrival);
  const std::unique_ptr<dds::PoseInbox> inbox = role_inbox(tools, boundary.pose_bounds);
  TrackerRegistration registration(boundary.reference_from_model, tools.reference);
  dds::BoundaryCounters counters;
  const auto admitted = [&](dds::SampleFault fault) {
    counters.count(fault);
    if (fault != dds::SampleFault::none) ++out.records_refused;
    return fault == dds::SampleFault::none;
  };
  for (const Arrival& a : arrivals) {
    const dds::RecordedSample record = reader.read(a.record).value();
    const TimeNs delivered_ns = a.received_ns - origin_ns;
    const TimeNs device_to_loop_ns = device_to_host_ns - origin_ns;
    if (record.topic == dds::Topic::tool_pose) {
      dds::SampleFault fault = dds::decode_sample(record.payload.data(), record.payload.size(), pose);
      if (fault == dds::SampleFault::none) fault = pose_boundary.admit(pose, a.received_ns);
      if (fault == dds::SampleFault::none) fault = inbox->offer(pose);
      if (!admitted(fault)) continue;
      const std::optional<DeviceSample> sample =
          device_sample_of(pose, device_to_loop_ns, delivered_ns, tools, registration);
      if (!sample) continue;  // the reference, or a pose before it
      ++out.poses;
      if (std::optional<DeviceSample> for_loop = loop_sample(observer, *sample, {})) samples.push_back(*for_loop);
      continue;
    }
    dds::SampleFault fault = dds::decode_sample(record.payload.data(), record.payload.size(), *frame);
    if (fault == dds::SampleFault::none) fault = frame_boundary.admit(*frame, a.received_ns);
    if (!admitted(fault)) continue;
    ++out.frames;
    DeviceSample sample;
    sample.kind = SampleKind::ultrasound_frame;
    sample.measured_ns = frame->source_time_ns + device_to_loop_ns;
    sample.delivered_ns = delivered_ns;
    const FrameView view{frame->pixels.data(), frame->width_px, frame->height_px, frame->pixel_spacing_m[0],
                         frame->pixel_spacing_m[1]};
    if (std::optional<DeviceSample> for_loop = loop_sample(observer, sample, view)) samples.push_back(*for_loop);
  }
  out.observer = observer.counts();
  out.boundary = counters.snapshot();
  return samples;
}

}  // namespace

Result<SessionReplay> replay_session(const Scene& scene, const std::string& path) {
  if (const Status runnable = check_station_loop(scene); !runnable.ok()) return runnable.error();
  auto reader = dds::RecordingReader::open(path);
  if (!reader.ok()) return reader.error();
  SessionReplay out;
  out.damage = reader.value()->damage();
  auto liver = make_station_liver(scene);
  if (!liver.ok()) return liver.error();
  auto loop = make_station_loop(liver.value(), scene, BreathingGeometry{}, StationLoopSettings{});
  if (!loop.ok()) return loop.error();
  auto imaging = scene_probe_imaging(scene);
  if (!imaging.ok()) return imaging.error();
  auto boundary = dds_run_options(scene, nullptr);
  if (!boundary.ok()) return boundary.error();
  auto samples = observed_session(*reader.value(), imaging.value(), boundary.value(), out);
  if (!samples.ok()) return samples.error();
  if (samples.value().empty())
    return Error{.message = "the recording holds no tracker poses or ultrasound frames to replay", .file = path};
  auto replay = replay_station(loop.value(), samples.value(), out.duration_ns, true);
  if (!replay.ok()) return replay.error();
  out.replay = std::move(replay).value();
  return out;
}

std::string format_replay(const Scene& scene, const std::string& path, const SessionReplay& r) {
  char text[1024];
  const TickRecord last = r.replay.ticks.empty() ? TickRecord{} : r.replay.ticks.back();
  std::snprintf(text, sizeof(text),
                "replay of %s through station '%s' on a simulated clock: %.3f s, %zu ticks\n"
                "  from the recording: %lld poses, %lld frames (%lld tumour points found), %lld records refused%s%s\n"
                "  refused at the station's boundary: %s\n"
                "  last tick: tumour now (%.2f, %.2f, %.2f) mm, needle tip (%.2f, %.2f, %.2f) mm\n"
                "  output hash %016llx\n",
                path.c_str(), scene.station.name.c_str(), 1e-9 * static_cast<double>(r.duration_ns),
                r.replay.ticks.size(), static_cast<long long>(r.poses), static_cast<long long>(r.frames),
                static_cast<long long>(r.observer.observations), static_cast<long long>(r.records_refused),
                r.damage ? "; damaged: " : "", r.damage ? r.damage->describe().c_str() : "",
                dds::drops_by_reason(r.boundary).c_str(), 1e3 * last.tumour_now_m[0], 1e3 * last.tumour_now_m[1],
                1e3 * last.tumour_now_m[2], 1e3 * last.needle_tip_m[0], 1e3 * last.needle_tip_m[1],
                1e3 * last.needle_tip_m[2], static_cast<unsigned long long>(r.replay.output_hash));
  return text;
}

}  // namespace nav::station
