#include "nav/station/world_player.hpp"

#include <algorithm>

namespace nav::station {

namespace {

dds::Vector3 vector_of(const Eigen::Vector3d& v) { return {v[0], v[1], v[2]}; }

}  // namespace

/// The reference tool's pose at the stamp of `respiratory` (written with it).
dds::ToolPose WorldPlayer::reference_pose(const dds::ToolPose& respiratory) const {
  dds::ToolPose pose = respiratory;
  pose.tool_id = *tracker_.tools.reference;
  dds::set_frame_name(pose.frame_from, "reference_marker");
  const RigidPose& r = tracker_.tracker_from_reference;
  pose.position_m = vector_of(r.position_m);
  pose.orientation_wxyz = {r.rotation.w(), r.rotation.x(), r.rotation.y(), r.rotation.z()};
  return pose;
}

SimulatedTracker simulated_tracker(const ToolIds& tools, const RigidPose& tracker_from_reference,
                                   const RigidPose& reference_from_model) {
  const RigidPose reference = tools.reference ? tracker_from_reference : RigidPose{};
  return {tools, compose(reference, reference_from_model), reference};
}

WorldPlayer::WorldPlayer(const SimulatedWorld& world, bool publish_truth, const SimulatedTracker& tracker)
    : world_(world),
      publish_truth_(publish_truth),
      tracker_(tracker),
      frame_(std::make_unique<dds::UltrasoundFrame>()),
      written_ns_(world.samples.size(), -1) {
  const ultrasound::BmodeGeometry& g = world.imaging.geometry;
  frame_->width_px = g.width_px;
  frame_->height_px = g.height_px;
  frame_->pixel_spacing_m = {g.spacing_m, g.spacing_m};
  frame_->depth_m = g.height_px * g.spacing_m;
  frame_->probe_tool_id = tracker.tools.probe;
}

void WorldPlayer::repeat_last(TimeNs period_ns) {
  repeat_period_ns_ = period_ns;
  cycle_.clear();
  for (std::size_t i = 0; i < world_.samples.size(); ++i) {
    const TimeNs measured_ns = world_.samples[i].measured_ns;
    if (measured_ns >= world_.duration_ns - period_ns && measured_ns < world_.duration_ns) cycle_.push_back(i);
  }
}

const DeviceSample* WorldPlayer::next_sample(TimeNs& later_ns) {
  later_ns = 0;
  if (repeats_ == 0) {
    // A repeating world leaves its samples at the end itself to the first repeat.
    while (next_ < world_.samples.size() && repeat_period_ns_ > 0 &&
           world_.samples[next_].measured_ns >= world_.duration_ns)
      ++next_;
    if (next_ < world_.samples.size()) return &world_.samples[next_];
    if (repeat_period_ns_ == 0 || cycle_.empty()) return nullptr;
    repeats_ = 1;
    next_ = 0;
  }
  if (next_ == cycle_.size()) {
    ++repeats_;
    next_ = 0;
  }
  later_ns = repeats_ * repeat_period_ns_;
  return &world_.samples[cycle_[next_]];
}

void WorldPlayer::write(const DeviceSample& s, TimeNs later_ns, dds::DdsNode& node, const MonotonicClock& clock) {
  const std::uint64_t sequence = sequence_++;
  TimeNs* written = sequence < written_ns_.size() && repeat_period_ns_ == 0 ? &written_ns_[sequence] : nullptr;
  const TimeNs to_device_ns = world_to_device_ns_ + later_ns;
  if (s.kind == SampleKind::ultrasound_frame) {
    const std::vector<std::uint8_t>& pixels = world_.frames[static_cast<std::size_t>(s.frame_index)].pixels;
    std::copy(pixels.begin(), pixels.end(), frame_->pixels.begin());
    frame_->sequence_number = sequence;
    frame_->source_time_ns = s.measured_ns + to_device_ns;
    if (written) *written = clock.now_ns();
    if (node.write(*frame_)) ++counts_.frames_written;
    return;
  }
  const dds::ToolPose pose = tool_pose_of(s, sequence, to_device_ns, tracker_);
  if (written) *written = clock.now_ns();
  if (node.write(pose)) ++counts_.poses_written;
  if (s.kind == SampleKind::respiratory && tracker_.tools.reference && node.write(reference_pose(pose)))
    ++counts_.poses_written;
}

TimeNs WorldPlayer::recording_time_ns(TimeNs time_ns) const noexcept {
  if (repeat_period_ns_ == 0 || time_ns < world_.duration_ns) return time_ns;
  return world_.duration_ns - repeat_period_ns_ + (time_ns - world_.duration_ns) % repeat_period_ns_;
}

void WorldPlayer::play_until(TimeNs now_ns, dds::DdsNode* node, const MonotonicClock& clock) {
  TimeNs later_ns = 0;
  for (const DeviceSample* s = next_sample(later_ns); s != nullptr && s->delivered_ns + later_ns <= now_ns;
       s = next_sample(later_ns)) {
    if (node == nullptr) {
      ++sequence_;
      ++counts_.samples_lost;
    } else {
      write(*s, later_ns, *node, clock);
    }
    ++next_;
  }
  if (!publish_truth_ || node == nullptr) return;
  const TimeNs recorded_end_ns = static_cast<TimeNs>(world_.tumour_truth_m.size() - 1) * world_.step_ns;
  const TimeNs truth_end_ns = repeat_period_ns_ > 0 ? now_ns : std::min(now_ns, recorded_end_ns);
  for (; next_truth_ns_ <= truth_end_ns; next_truth_ns_ += world_.step_ns) {
    dds::GroundTruth truth;
    truth.source_time_ns = next_truth_ns_ + world_to_device_ns_;
    const TimeNs recorded_ns = recording_time_ns(next_truth_ns_);
    const Point3 tumour = world_.tumour_at(recorded_ns);
    truth.tumour_m = {tumour[0], tumour[1], tumour[2]};
    truth.needle_tip_m = vector_of(world_.needle_tip_at(recorded_ns));
    if (node->write(truth)) ++counts_.truths_written;
  }
}

dds::ToolPose tool_pose_of(const DeviceSample& sample, std::uint64_t sequence_number, TimeNs world_to_device_ns,
                           const SimulatedTracker& tracker) {
  dds::ToolPose pose;
  pose.sequence_number = sequence_number;
  pose.source_time_ns = sample.measured_ns + world_to_device_ns;
  pose.quality = 1.0f;
  dds::set_frame_name(pose.frame_to, "tracker");
  const ToolIds& tools = tracker.tools;
  if (sample.kind == SampleKind::respiratory) {
    pose.tool_id = tools.respiratory;
    const RigidPose& t = tracker.tracker_from_model;
    pose.position_m = vector_of(t.rotation * sample.point_m + t.position_m);
    dds::set_frame_name(pose.frame_from, "respiratory_marker");
    return pose;
  }
  const bool needle = sample.kind == SampleKind::needle_pose;
  pose.tool_id = needle ? tools.needle : tools.probe;
  dds::set_frame_name(pose.frame_from, needle ? "needle_base" : "probe_marker");
  const RigidPose in_tracker = compose(tracker.tracker_from_model, sample.pose);
  const Eigen::Quaterniond& q = in_tracker.rotation;
  pose.position_m = vector_of(in_tracker.position_m);
  pose.orientation_wxyz = {q.w(), q.x(), q.y(), q.z()};
  return pose;
}

}  // namespace nav::station
