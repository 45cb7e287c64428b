#include "nav/station/station_dds.hpp"

#include <algorithm>
#include <limits>
#include <thread>
#include <utility>
#include <vector>

#include "nav/core/health.hpp"
#include "nav/station/display_surface.hpp"
#include "nav/station/station_build.hpp"
#include "nav/station/station_channels.hpp"
#include "nav/station/world_player.hpp"

namespace nav::station {

namespace {

constexpr TimeNs kMatchTimeoutNs = 10 * kNsPerSecond;
constexpr TimeNs kAcknowledgmentTimeoutNs = 1 * kNsPerSecond;
constexpr TimeNs kPeerWatchPeriodNs = 5 * kNsPerMs;  // how often the I/O thread counts the matched pose writers
constexpr std::uint32_t kTumourTargetId = 1;
static_assert(kLoopMaxNeedleNodes <= static_cast<int>(dds::kMaxNeedlePoints),
              "a NeedleState holds every node of the loop's needle");

dds::Vector3 vector_of(const Point3& p) { return {p[0], p[1], p[2]}; }

/// A sample received by the station: its sequence number (the recording's index) and when.
struct Receipt {
  std::uint64_t sequence_number = 0;
  TimeNs received_ns = 0;  ///< monotonic clock
};

/// Writer-to-reader latencies (microseconds) of the receipts whose write time is known.
std::vector<double> latencies_us(const std::vector<Receipt>& receipts, const std::vector<TimeNs>& written_ns) {
  std::vector<double> latency;
  latency.reserve(receipts.size());
  for (const Receipt& r : receipts)
    if (r.sequence_number < written_ns.size() && written_ns[r.sequence_number] >= 0)
      latency.push_back(1e-3 * static_cast<double>(r.received_ns - written_ns[r.sequence_number]));
  return latency;
}

/// The devices' side: plays the world's recording on its own participant, each sample when
/// its delivery time comes; during an outage the participant is destroyed (and the samples
/// due are lost), then created again.
void device_thread(WorldPlayer& player, StationChannels& ch, const DdsRunOptions& options, StationDdsLink& link,
                   DdsRunReport& report) {
  // The simulated devices stamp on their clock: this host's monotonic clock less the scene's
  // declared offset (the station adds it back).
  player.set_world_to_device_ns(ch.start_ns - options.arrival.source_clock_offset_ns);
  while (!ch.realtime_done.load(std::memory_order_acquire) && !player.finished()) {
    const TimeNs now = ch.run_time_ns();
    if (options.device_outage && report.device_gone_ns < 0 && now >= options.device_outage->from_ns) {
      report.device_gone_ns = ch.run_time_ns();
      link.devices.reset();  // the participant goes away: its writers are announced as gone
    }
    if (options.device_outage && !link.devices && now >= options.device_outage->to_ns) {
      // Timed before the creation: the station's reader may discover the writers while they
      // are still being advertised.
      const TimeNs creating_ns = ch.run_time_ns();
      auto node = make_station_node(link.domain_id, "nav_demo_devices", link.names, link.network, Role::devices);
      if (node.ok() && node.value()->advertise<dds::ToolPose>().ok() &&
          node.value()->advertise<dds::UltrasoundFrame>().ok()) {
        link.devices = std::move(node).value();
        report.device_back_ns = creating_ns;
      }
    }
    player.play_until(now, link.devices.get(), ch.clock);
    ch.clock.sleep_until_ns(ch.clock.now_ns() + kIoPeriodNs);
  }
}

/// Publishes the deformed surface from the outputs at the surface period of liver time, when
/// the run has a surface (I/O thread).
class DisplaySurfacePublisher {
 public:
  DisplaySurfacePublisher(const OperatingLoopModel& loop, const DdsRunOptions& options)
      : period_ns_(options.surface_period_ns) {
    if (options.surface == nullptr) return;
    auto made = SurfaceReconstruction::create(loop, *options.surface);
    if (!made.ok()) return;
    reconstruction_.emplace(std::move(made).value());
    sample_ = std::make_unique<dds::DeformedSurface>();
    reconstruction_us_.reserve(1024);
  }

  /// Publishes the surface of `outputs` (loop time; stamped loop time + loop_to_host_ns) when its period has come.
  void publish(const OperatingLoopOutputs& outputs, TimeNs loop_to_host_ns, dds::DdsNode& node) {
    if (!reconstruction_ || outputs.tissue_steps == 0 || outputs.tissue_time_ns < next_ns_) return;
    const TimeNs begin_ns = clock_.now_ns();
    reconstruction_->reconstruct(outputs, *sample_);
    sample_->source_time_ns += loop_to_host_ns;
    reconstruction_us_.push_back(1e-3 * static_cast<double>(clock_.now_ns() - begin_ns));
    if (node.write(*sample_)) ++published_;
    passed_over_ += (outputs.tissue_time_ns - next_ns_) / period_ns_;
    next_ns_ = (outputs.tissue_time_ns / period_ns_ + 1) * period_ns_;  // one surface per period of liver time
  }

  std::int64_t published() const noexcept { return published_; }
  /// Periods of liver time with no surface: the I/O thread read no output within them.
  std::int64_t passed_over() const noexcept { return passed_over_; }
  const std::vector<double>& reconstruction_us() const noexcept { return reconstruction_us_; }

 private:
  TimeNs period_ns_;
  std::optional<SurfaceReconstruction> reconstruction_;
  std::unique_ptr<dds::DeformedSurface> sample_;
  std::vector<double> reconstruction_us_;
  std::int64_t published_ = 0, passed_over_ = 0;
  TimeNs next_ns_ = 0;
  MonotonicClock clock_;
};

/// Each input's samples refused so far: the needle's, probe's and respiratory marker's poses
/// (by the inbox, whatever refused them) and the ultrasound's frames (by their reader).
dds::PerInput<std::uint64_t> input_refusals(const StationDdsLink& link) {
  const dds::PoseInbox& poses = *link.poses;
  const auto of_tool = [&poses](std::uint32_t tool_id) {
    const int slot = poses.slot_of(tool_id);
    return slot < 0 ? std::uint64_t{0} : poses.refused(static_cast<std::size_t>(slot));
  };
  return {of_tool(link.tools.needle), of_tool(link.tools.probe), of_tool(link.tools.respiratory),
          dds::refused_as_invalid(link.station->boundary_counts(dds::Topic::ultrasound_frame))};
}

/// The station's outputs on DDS, on a thread of their own beside the I/O thread (its core, one
/// SCHED_FIFO priority above it where the loop's allows): the outbox (predictions, needle
/// states, health) as soon as the loop pushes it and the deformed surface, so that a frame
/// being searched for the tumour on the I/O thread never holds a prediction back.
void output_thread(StationChannels& ch, const StationRunOptions& options, StationDdsLink& link,
                   DisplaySurfacePublisher& surfaces, StationRun& run, DdsRunReport& report) {
  pin_to_core(options.io_core);
  if (options.io_priority > 0)
    request_fifo(options.io_priority + 1 < options.realtime.priority ? options.io_priority + 1 : options.io_priority);
  dds::OutboxPublisher publisher(options.dds->bad_sample_hold_ns);
  const auto publish = [&] {
    report.outputs_published += static_cast<std::int64_t>(
        publisher.publish(*ch.outbox, *link.station, ch.clock.now_ns(), input_refusals(link)));
    if (!ch.outputs.update()) return;
    ++run.outputs_read;
    surfaces.publish(ch.outputs.read(), ch.start_ns, *link.station);
  };
  ch.wait_for_start();
  while (!ch.realtime_done.load(std::memory_order_acquire)) {
    publish();
    ch.clock.sleep_until_ns(ch.clock.now_ns() + kIoPeriodNs);
  }
  publish();                                                         // the loop's last outputs
  link.station->wait_for_acknowledgments(kAcknowledgmentTimeoutNs);  // they reach the displays before the run closes
  report.outbox_dropped = ch.outbox->dropped();
  report.forces_published = static_cast<std::int64_t>(publisher.forces_written());
  report.forces_dropped = ch.outbox->needle_forces.dropped();
}

/// Watches whether the station still has a pose writer matched, and records the changes.
void watch_peer(const dds::DdsNode& station, TimeNs now, bool& present, DdsRunReport& report) {
  const bool matched = station.matched(dds::Topic::tool_pose) > 0;
  if (present && !matched && report.peer_lost_seen_ns < 0) report.peer_lost_seen_ns = now;
  if (!present && matched && report.peer_lost_seen_ns >= 0 && report.peer_back_seen_ns < 0)
    report.peer_back_seen_ns = now;
  present = matched;
}

}  // namespace

std::optional<DeviceSample> device_sample_of(const dds::ToolPose& pose, TimeNs device_to_loop_ns, TimeNs received_ns,
                                             const ToolIds& tools, TrackerRegistration& registration) {
  if (registration.take_reference(pose)) return std::nullopt;
  const bool respiratory = pose.tool_id == tools.respiratory;
  if (!respiratory && pose.tool_id != tools.needle && pose.tool_id != tools.probe) return std::nullopt;
  const std::optional<RigidPose> model_from_tracker = registration.model_from_tracker();
  if (!model_from_tracker) {
    ++registration.unregistered_poses;
    return std::nullopt;
  }
  DeviceSample s;
  s.measured_ns = pose.source_time_ns + device_to_loop_ns;
  s.delivered_ns = received_ns;
  const auto& q = pose.orientation_wxyz;
  const RigidPose in_tracker{{pose.position_m[0], pose.position_m[1], pose.position_m[2]},
                             Eigen::Quaterniond(q[0], q[1], q[2], q[3]).normalized()};
  const RigidPose in_model = compose(*model_from_tracker, in_tracker);
  if (respiratory) {  // a position only
    s.kind = SampleKind::respiratory;
    s.point_m = in_model.position_m;
    return s;
  }
  s.kind = pose.tool_id == tools.needle ? SampleKind::needle_pose : SampleKind::probe_pose;
  s.pose = in_model;
  return s;
}

std::unique_ptr<dds::PoseInbox> role_inbox(const ToolIds& t, const dds::PoseBounds& bounds) {
  if (t.reference)
    return std::make_unique<dds::PoseInbox>(
        std::initializer_list<std::uint32_t>{*t.reference, t.needle, t.probe, t.respiratory}, bounds);
  return std::make_unique<dds::PoseInbox>(std::initializer_list<std::uint32_t>{t.needle, t.probe, t.respiratory},
                                          bounds);
}

dds::TopicNames topic_names(const TopicSettings& topics) {
  dds::TopicNames names;
  const auto set = [&names](dds::Topic topic, const std::string& name) {
    names[static_cast<std::size_t>(topic)] = name;
  };
  set(dds::Topic::tool_pose, topics.poses);
  set(dds::Topic::ultrasound_frame, topics.images);
  set(dds::Topic::needle_state, topics.needle_states);
  set(dds::Topic::needle_force, topics.needle_forces);
  set(dds::Topic::target_prediction, topics.predictions);
  set(dds::Topic::deformed_surface, topics.surfaces);
  set(dds::Topic::station_health, topics.health);
  set(dds::Topic::ground_truth, topics.ground_truth);
  return names;
}

dds::NetworkConfig station_network(std::uint32_t domain_id, const char* participant_name,
                                   const NetworkSettings& settings, Role role) {
  dds::NetworkConfig network;  // the defaults: shared memory and UDP on 127.0.0.1, unicast discovery, no multicast
  network.domain_id = domain_id;
  network.participant_name = participant_name;
  network.local_address = settings.local_address;
  network.peer_addresses = settings.peers;
  network.security = security_files(settings.security, role);
  // Participant ids grow with every participant a process creates (the devices' participant
  // comes back after an outage; a test process makes a dozen): probe more than the default 8.
  network.max_participants_per_host = 32;
  return network;
}

Result<SceneDds> scene_dds(const std::string& scene_path, Role role) {
  auto scene = load_scene(scene_path);
  if (!scene.ok()) return scene.error();
  return SceneDds{station_network(scene.value().topics.domain_id, "", scene.value().network, role),
                  topic_names(scene.value().topics)};
}

Result<std::unique_ptr<dds::DdsNode>> make_station_node(std::uint32_t domain_id, const char* participant_name,
                                                        const dds::TopicNames& names, const NetworkSettings& network,
                                                        Role role) {
  dds::TopicQosOptions qos;
  qos.names = names;
  return dds::DdsNode::create(station_network(domain_id, participant_name, network, role), qos);
}

Result<std::unique_ptr<StationDdsLink>> StationDdsLink::create(std::uint32_t domain_id, const dds::TopicNames& names,
                                                               const dds::ArrivalWindow& arrival,
                                                               const dds::PoseBounds& pose_bounds,
                                                               bool with_simulated_devices,
                                                               const NetworkSettings& network, const ToolIds& tools) {
  auto link = std::make_unique<StationDdsLink>();
  link->poses = role_inbox(tools, pose_bounds);
  link->domain_id = domain_id;
  link->names = names;
  link->network = network;
  link->tools = tools;
  auto station = make_station_node(domain_id, "nav_station", names, network);
  if (!station.ok()) return station.error();
  link->station = std::move(station).value();
  dds::DdsNode& s = *link->station;
  for (const Status& status :
       {s.subscribe(*link->poses, arrival), s.subscribe(*link->frames, arrival), s.advertise<dds::TargetPrediction>(),
        s.advertise<dds::NeedleState>(), s.advertise<dds::StationHealth>(), s.advertise<dds::DeformedSurface>(),
        s.advertise<dds::NeedleForce>()})
    if (!status.ok()) return status.error();
  if (!with_simulated_devices) return link;  // the devices are other processes: they come and go
  auto devices = make_station_node(domain_id, "nav_demo_devices", names, network, Role::devices);
  if (!devices.ok()) return devices.error();
  link->devices = std::move(devices).value();
  dds::DdsNode& d = *link->devices;
  for (const Status& status : {d.advertise<dds::ToolPose>(), d.advertise<dds::UltrasoundFrame>()})
    if (!status.ok()) return status.error();
  if (!s.wait_for_match(dds::Topic::tool_pose, 1, kMatchTimeoutNs) ||
      !s.wait_for_match(dds::Topic::ultrasound_frame, 1, kMatchTimeoutNs) ||
      !d.wait_for_match(dds::Topic::tool_pose, 1, kMatchTimeoutNs) ||
      !d.wait_for_match(dds::Topic::ultrasound_frame, 1, kMatchTimeoutNs))
    return Error{.message = "the devices' and the station's DDS participants did not match within 10 s",
                 .field = "domain " + std::to_string(domain_id)};
  return link;
}

void push_outputs(dds::StationOutbox& outbox, const OperatingLoopOutputs& o, const OutputStamps& stamps,
                  std::int64_t health_every_ticks, std::uint64_t deadline_misses, TimeNs step_max_ns) noexcept {
  const TimeNs loop_to_host_ns = stamps.loop_to_host_ns;
  if (o.time_ns == o.tissue_time_ns) {
    dds::TargetPrediction prediction;
    prediction.source_time_ns = o.tissue_time_ns + loop_to_host_ns;
    prediction.target_id = kTumourTargetId;
    prediction.model_rung = static_cast<std::uint32_t>(o.liver_rung);
    prediction.position_m = vector_of(o.tumour_now_m);
    prediction.covariance_m2 = o.tumour_now_covariance_m2;
    outbox.predictions.try_push(prediction);
    prediction.horizon_ns = stamps.display_latency_ns;
    prediction.position_m = vector_of(o.tumour_ahead_m);
    prediction.covariance_m2 = o.tumour_ahead_covariance_m2;
    outbox.predictions.try_push(prediction);
    dds::NeedleState needle;
    needle.source_time_ns = o.time_ns + loop_to_host_ns;
    needle.tool_id = stamps.needle_tool_id;
    const NeedleShapeOutputs& shape = o.needle_shape;
    if (shape.node_count > 0) {  // the loop steps a needle model: its centreline, base to tip, and the tip force
      needle.point_count = static_cast<std::uint32_t>(shape.node_count);
      for (std::size_t i = 0; i < needle.point_count; ++i) needle.shape_points_m[i] = vector_of(shape.centreline_m[i]);
      needle.tip_force_n = vector_of(shape.tip_force_n);
    } else {  // the loop tracks the tip only
      needle.point_count = 1;
      needle.shape_points_m[0] = vector_of(o.needle_tip_m);
    }
    outbox.needle.try_push(needle);
  }
  if (o.needle_shape.node_count > 0) {  // the needle model's forces at every tick
    dds::NeedleForce force;
    force.source_time_ns = o.time_ns + loop_to_host_ns;
    force.tool_id = stamps.needle_tool_id;
    force.flags = o.needle_shape.flags.bits();
    force.tip_force_n = vector_of(o.needle_shape.tip_force_n);
    force.holder_force_n = vector_of(o.needle_shape.base_force_n);
    outbox.needle_forces.try_push(force);
  }
  if (o.ticks % health_every_ticks != 0) return;
  dds::StationHealth health;
  health.source_time_ns = o.time_ns + loop_to_host_ns;
  health.mode = o.degraded ? dds::StationMode::degraded : dds::StationMode::running;
  health.flags = health_flag_bits(o);
  health.input_flags = {o.needle.flags.bits(), o.probe.flags.bits(), o.respiratory.flags.bits(),
                        o.ultrasound.flags.bits()};
  const InputStatus* inputs[] = {&o.needle, &o.probe, &o.respiratory, &o.ultrasound};
  for (std::size_t i = 0; i < dds::kStationInputCount; ++i)
    health.input_age_ns[i] =
        inputs[i]->age_ns == std::numeric_limits<TimeNs>::max() ? dds::StationHealth::kNoSampleYet : inputs[i]->age_ns;
  health.step_time_max_ns = step_max_ns;
  health.deadline_misses = deadline_misses;
  outbox.health.try_push(health);
}

void dds_io_thread(const OperatingLoopModel& loop, const SimulatedWorld* world, const ProbeImaging& imaging,
                   StationChannels& ch, StationRun& run, const StationRunOptions& options, StationDdsLink& link) {
  setup_io_thread(options, run);
  TumourObserver observer(imaging, options.observer);
  DdsRunReport report;
  auto frame = std::make_unique<dds::UltrasoundFrame>();
  std::vector<Receipt> pose_receipts, frame_receipts;
  if (world != nullptr) {  // the in-process devices' samples are timed from their write to the station's listener
    pose_receipts.reserve(world->samples.size());
    frame_receipts.reserve(world->frames.size());
  }
  DisplaySurfacePublisher surfaces(loop, *options.dds);
  std::optional<WorldPlayer> player;
  if (world != nullptr)
    player.emplace(*world, false,
                   simulated_tracker(link.tools, options.dds->simulated_tracker_from_reference,
                                     options.dds->reference_from_model));
  TrackerRegistration registration(options.dds->reference_from_model, link.tools.reference);
  ch.wait_for_start();
  run.resident_at_start_bytes = resident_bytes();  // every buffer is in, locked with the loop's memory
  const TimeNs device_to_loop_ns =
      options.dds->arrival.source_clock_offset_ns - ch.start_ns;  // stamps onto the loop's clock
  std::thread devices;
  if (player)
    devices = std::thread(device_thread, std::ref(*player), std::ref(ch), std::cref(*options.dds), std::ref(link),
                          std::ref(report));
  DdsRunReport published;  // the output thread's part of the report
  std::thread outputs(output_thread, std::ref(ch), std::cref(options), std::ref(link), std::ref(surfaces),
                      std::ref(run), std::ref(published));
  bool peer_present = link.devices != nullptr;
  TimeNs next_watch_ns = 0;
  while (!ch.realtime_done.load(std::memory_order_acquire)) {
    for (std::size_t slot = 0; slot < link.poses->tool_count(); ++slot) {
      if (!link.poses->update(slot)) continue;
      const dds::ToolPose& pose = link.poses->latest(slot);
      const TimeNs received_ns = pose.receive_time_ns - ch.start_ns;
      ++report.poses_received;
      if (player) pose_receipts.push_back({pose.sequence_number, pose.receive_time_ns});
      const std::optional<DeviceSample> sample =
          device_sample_of(pose, device_to_loop_ns, received_ns, link.tools, registration);
      if (!sample) continue;
      const std::optional<DeviceSample> for_loop = loop_sample(observer, *sample, {});
      if (for_loop && ch.samples.try_push(*for_loop)) ++run.samples_pushed;
    }
    while (link.frames->try_pop(*frame)) {
      const TimeNs received_ns = frame->receive_time_ns - ch.start_ns;
      ++report.frames_received;
      if (player) frame_receipts.push_back({frame->sequence_number, frame->receive_time_ns});
      DeviceSample sample;
      sample.kind = SampleKind::ultrasound_frame;
      sample.measured_ns = frame->source_time_ns + device_to_loop_ns;
      sample.delivered_ns = received_ns;
      const FrameView view{frame->pixels.data(), frame->width_px, frame->height_px, frame->pixel_spacing_m[0],
                           frame->pixel_spacing_m[1]};
      const std::optional<DeviceSample> for_loop = loop_sample(observer, sample, view);
      if (for_loop && ch.samples.try_push(*for_loop)) ++run.samples_pushed;
    }
    const TimeNs now = ch.run_time_ns();
    if (now >= next_watch_ns) {
      watch_peer(*link.station, now, peer_present, report);
      next_watch_ns = now + kPeerWatchPeriodNs;
    }
    ch.clock.sleep_until_ns(ch.clock.now_ns() + kIoPeriodNs);
  }
  if (devices.joinable()) devices.join();
  outputs.join();
  report.outputs_published = published.outputs_published;
  report.outbox_dropped = published.outbox_dropped;
  report.forces_published = published.forces_published;
  report.forces_dropped = published.forces_dropped;
  if (player) {
    const PlayerCounts& played = player->counts();
    report.poses_written = played.poses_written;
    report.frames_written = played.frames_written;
    report.device_samples_lost = played.samples_lost;
    report.pose_latency = latency_statistics(latencies_us(pose_receipts, player->written_ns()));
    report.frame_latency = latency_statistics(latencies_us(frame_receipts, player->written_ns()));
  }
  run.observer = observer.counts();
  run.frame_processing = latency_statistics(observer.processing_us());
  report.poses_accepted = static_cast<std::int64_t>(link.poses->accepted());
  report.surfaces_published = surfaces.published();
  report.surface_periods_passed_over = surfaces.passed_over();
  report.surface_reconstruction = latency_statistics(surfaces.reconstruction_us());
  report.boundary = link.station->boundary_counts();
  report.input_refused = input_refusals(link);
  report.poses_lost = link.station->samples_lost(dds::Topic::tool_pose);
  report.frames_lost = link.station->samples_lost(dds::Topic::ultrasound_frame);
  report.unregistered_poses = registration.unregistered_poses;
  run.dds = report;
}

}  // namespace nav::station
