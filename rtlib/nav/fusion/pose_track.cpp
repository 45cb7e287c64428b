#include "nav/fusion/pose_track.hpp"

#include <cmath>
#include <string>

namespace nav {
namespace {

Error track_option_error(const char* field, const std::string& message) {
  return Error{.message = message, .field = std::string("pose_track.") + field};
}

bool finite_unit_pose(const RigidPose& pose, double tolerance) noexcept {
  if (!pose.position_m.allFinite() || !pose.rotation.coeffs().allFinite()) return false;
  return std::abs(pose.rotation.norm() - 1.0) <= tolerance;
}

}  // namespace

Result<PoseTrack> PoseTrack::create(const PoseTrackOptions& options) {
  if (options.capacity < 2) return track_option_error("capacity", "must hold at least 2 samples");
  if (options.max_age_ns <= 0) return track_option_error("max_age_ns", "must be positive");
  if (options.missing_after_ns < options.max_age_ns)
    return track_option_error("missing_after_ns", "must be at least max_age_ns");
  if (options.max_extrapolation_ns < 0) return track_option_error("max_extrapolation_ns", "must not be negative");
  if (options.fit_window_ns < 0) return track_option_error("fit_window_ns", "must not be negative");
  if (!(options.max_speed_m_s > 0.0)) return track_option_error("max_speed_m_s", "must be positive");
  if (!(options.max_angular_speed_rad_s > 0.0))
    return track_option_error("max_angular_speed_rad_s", "must be positive");
  if (!(options.jump_allowance_m >= 0.0)) return track_option_error("jump_allowance_m", "must not be negative");
  if (!(options.jump_allowance_rad >= 0.0)) return track_option_error("jump_allowance_rad", "must not be negative");
  if (options.jump_confirmations < 1) return track_option_error("jump_confirmations", "must be at least 1");
  if (options.recovery_samples < 1) return track_option_error("recovery_samples", "must be at least 1");
  if (!(options.unit_quaternion_tolerance > 0.0))
    return track_option_error("unit_quaternion_tolerance", "must be positive");
  return PoseTrack(options);
}

PoseTrack::PoseTrack(const PoseTrackOptions& options) : options_(options), samples_(options.capacity) {}

bool PoseTrack::is_jump(const TimedPose& from, const TimedPose& to) const noexcept {
  const double dt_s = seconds_of(to.time_ns - from.time_ns);
  const double distance_m = (to.pose.position_m - from.pose.position_m).norm();
  const double angle_rad = relative_rotation_vector(from.pose.rotation, to.pose.rotation).norm();
  return distance_m > options_.max_speed_m_s * dt_s + options_.jump_allowance_m ||
         angle_rad > options_.max_angular_speed_rad_s * dt_s + options_.jump_allowance_rad;
}

HealthFlags PoseTrack::reject(HealthFlags flags) noexcept {
  degraded_ = true;
  degraded_flags_.merge(flags);
  consecutive_good_ = 0;
  return flags;
}

void PoseTrack::accept(const TimedPose& sample, bool restart) noexcept {
  if (restart) {
    samples_.clear();
    degraded_ = true;
    consecutive_good_ = 0;
  }
  samples_.push(sample);
  jump_candidates_ = 0;
  if (++consecutive_good_ >= options_.recovery_samples) {
    degraded_ = false;
    degraded_flags_.clear_all();
  }
}

HealthFlags PoseTrack::push(const TimedPose& raw) noexcept {
  HealthFlags flags;
  if (!finite_unit_pose(raw.pose, options_.unit_quaternion_tolerance)) {
    flags.raise(HealthFlag::bad_sample);
    return reject(flags);
  }
  TimedPose sample = raw;
  sample.pose.rotation.normalize();
  if (samples_.empty()) {
    accept(sample, false);
    return flags;
  }
  const TimedPose& newest = samples_.newest();
  const bool backwards = sample.time_ns <= newest.time_ns;
  if (!backwards && sample.time_ns - newest.time_ns > options_.max_age_ns) {
    accept(sample, true);  // back from a dropout: a fresh start
    return flags;
  }
  if (!backwards && !is_jump(newest, sample)) {
    accept(sample, false);
    return flags;
  }
  // Rejected, unless it ends a run of rejected samples that agree with each other: then the
  // tool (or its clock) really moved, and the track re-acquires it rather than locking out.
  const bool agrees =
      jump_candidates_ > 0 && sample.time_ns > jump_candidate_.time_ns && !is_jump(jump_candidate_, sample);
  jump_candidates_ = agrees ? jump_candidates_ + 1 : 1;
  jump_candidate_ = sample;
  if (jump_candidates_ >= options_.jump_confirmations) {
    accept(sample, true);
    return flags;
  }
  flags.raise(backwards ? HealthFlag::clock_went_backwards : HealthFlag::pose_jump_rejected);
  return reject(flags);
}

RigidPose PoseTrack::extrapolated(TimeNs horizon_ns) const noexcept {
  const std::size_t count = samples_.size();
  const TimedPose& newest = samples_.newest();
  const TimedPose& previous = samples_.at(count - 2);
  if (options_.fit_window_ns > 0 && newest.time_ns - previous.time_ns <= options_.fit_window_ns)
    return fitted(horizon_ns);
  const TimeNs span_ns = newest.time_ns - previous.time_ns;
  const double fraction = static_cast<double>(span_ns + horizon_ns) / static_cast<double>(span_ns);
  return geodesic(previous.pose, newest.pose, fraction);
}

/// The least-squares line through the samples within the window (times in seconds from the
/// newest; rotations as rotation vectors in the newest's frame), evaluated horizon_ns past it.
RigidPose PoseTrack::fitted(TimeNs horizon_ns) const noexcept {
  const std::size_t count = samples_.size();
  const TimedPose& newest = samples_.newest();
  std::size_t first = count - 2;
  while (first > 0 && newest.time_ns - samples_.at(first - 1).time_ns <= options_.fit_window_ns) --first;
  const auto n = static_cast<double>(count - first);
  double mean_s = 0.0;
  Eigen::Vector3d mean_m = Eigen::Vector3d::Zero(), mean_rad = Eigen::Vector3d::Zero();
  for (std::size_t k = first; k < count; ++k) {
    const TimedPose& s = samples_.at(k);
    mean_s += seconds_of(s.time_ns - newest.time_ns);
    mean_m += s.pose.position_m;
    mean_rad += relative_rotation_vector(newest.pose.rotation, s.pose.rotation);
  }
  mean_s /= n, mean_m /= n, mean_rad /= n;
  double spread_s2 = 0.0;
  Eigen::Vector3d velocity_m = Eigen::Vector3d::Zero(), velocity_rad = Eigen::Vector3d::Zero();
  for (std::size_t k = first; k < count; ++k) {
    const TimedPose& s = samples_.at(k);
    const double t = seconds_of(s.time_ns - newest.time_ns) - mean_s;
    spread_s2 += t * t;
    velocity_m += t * (s.pose.position_m - mean_m);
    velocity_rad += t * (relative_rotation_vector(newest.pose.rotation, s.pose.rotation) - mean_rad);
  }
  const double lever_s = (seconds_of(horizon_ns) - mean_s) / spread_s2;
  return {mean_m + lever_s * velocity_m,
          newest.pose.rotation * quaternion_from_rotation_vector(mean_rad + lever_s * velocity_rad)};
}

PoseQuery PoseTrack::sample_at(TimeNs time_ns) const noexcept {
  PoseQuery query;
  if (samples_.empty()) {
    query.flags.raise(HealthFlag::missing_input);
    return query;
  }
  if (degraded_) query.flags.merge(degraded_flags_);
  const TimedPose& newest = samples_.newest();
  const std::size_t count = samples_.size();
  query.age_ns = time_ns - newest.time_ns;
  if (time_ns > newest.time_ns) {
    query.extrapolated = true;
    const TimeNs horizon_ns =
        query.age_ns < options_.max_extrapolation_ns ? query.age_ns : options_.max_extrapolation_ns;
    query.pose = count >= 2 ? extrapolated(horizon_ns) : newest.pose;
    if (query.age_ns > options_.max_age_ns || query.age_ns > options_.max_extrapolation_ns)
      query.flags.raise(HealthFlag::stale_input);
    if (query.age_ns > options_.missing_after_ns) query.flags.raise(HealthFlag::missing_input);
  } else if (time_ns <= samples_.at(0).time_ns) {
    query.pose = samples_.at(0).pose;  // before the history: the oldest pose kept
    if (time_ns < samples_.at(0).time_ns) query.flags.raise(HealthFlag::stale_input);
  } else {
    // Binary search for the bracketing pair: at(low).time < time_ns <= at(high).time.
    std::size_t low = 0;
    std::size_t high = count - 1;
    while (high - low > 1) {
      const std::size_t middle = low + (high - low) / 2;
      if (samples_.at(middle).time_ns < time_ns)
        low = middle;
      else
        high = middle;
    }
    const TimedPose& a = samples_.at(low);
    const TimedPose& b = samples_.at(high);
    const double fraction = static_cast<double>(time_ns - a.time_ns) / static_cast<double>(b.time_ns - a.time_ns);
    query.pose = geodesic(a.pose, b.pose, fraction);
  }
  query.degraded = degraded_ || query.flags.has(HealthFlag::stale_input) || query.flags.has(HealthFlag::missing_input);
  return query;
}

}  // namespace nav
