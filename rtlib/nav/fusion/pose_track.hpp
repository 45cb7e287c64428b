#pragma once
// The recent history of one tracked tool's pose, and its pose at any tick: interpolated
// between timestamped samples (SLERP), or extrapolated at constant velocity to compensate
// latency (the velocity of the last two samples, or of a least-squares fit over a window). Bad samples, backward clocks
// and jumps are rejected and flagged; stale or missing data puts the track in degraded mode until enough good samples
// return.
#include <cstddef>

#include "nav/core/clock.hpp"
#include "nav/core/error.hpp"
#include "nav/core/health.hpp"
#include "nav/fusion/history_ring.hpp"
#include "nav/fusion/rigid_pose.hpp"

namespace nav {

/// Capacities, ages and limits of a PoseTrack; checked by PoseTrack::create.
struct PoseTrackOptions {
  std::size_t capacity = 64;                    // samples kept (>= 2)
  TimeNs max_age_ns = 50 * kNsPerMs;            // newest sample older than this: stale_input
  TimeNs missing_after_ns = 500 * kNsPerMs;     // newest sample older than this: missing_input too
  TimeNs max_extrapolation_ns = 30 * kNsPerMs;  // beyond this the extrapolated pose is held
  /// 0: extrapolate along the last two samples. Above 0: along the least-squares
  /// constant-velocity fit of the samples measured within this of the newest (position, and
  /// rotation vectors about the newest), which keeps a noisy tracker's noise from being
  /// multiplied by the extrapolation; a fixed cost of at most `capacity` samples.
  TimeNs fit_window_ns = 0;
  double max_speed_m_s = 2.0;               // faster between samples: a jump
  double max_angular_speed_rad_s = 20.0;    // faster turn between samples: a jump
  double jump_allowance_m = 1e-3;           // noise allowed on top of max_speed_m_s * dt
  double jump_allowance_rad = 0.01;         // noise allowed on top of the angular limit
  int jump_confirmations = 3;               // consecutive agreeing rejected samples that re-acquire
  int recovery_samples = 3;                 // consecutive good samples that end degraded mode
  double unit_quaternion_tolerance = 1e-6;  // | |q| - 1 | above this: bad_sample
};

/// A pose looked up for one tick, with what was wrong with the data behind it.
struct PoseQuery {
  RigidPose pose;
  HealthFlags flags;          // stale_input, missing_input, and the rejections behind degraded mode
  bool degraded = true;       // flags raised, or the track has not yet recovered
  bool extrapolated = false;  // the time is after the newest sample
  TimeNs age_ns = 0;          // query time minus the newest sample's time
};

/// Fixed-capacity track of one tool's timestamped poses. create() allocates; push() and
/// sample_at() never allocate, throw or make system calls, and are deterministic.
class PoseTrack {
 public:
  /// A track with storage for `options.capacity` samples, or an Error naming the bad field.
  static Result<PoseTrack> create(const PoseTrackOptions& options);

  /// Validates and stores a sample. Returns the flags of a rejection (bad_sample,
  /// clock_went_backwards, pose_jump_rejected), empty when the sample was accepted. A sample
  /// more than max_age_ns after the newest restarts the track (the tool may have moved
  /// anywhere during the dropout); `jump_confirmations` consecutive rejected samples (jumped,
  /// or behind the clock) that agree with each other are accepted as a re-acquisition, so a
  /// track never locks out.
  HealthFlags push(const TimedPose& sample) noexcept;

  /// The pose at `time_ns`: SLERP between the bracketing samples; past the newest sample,
  /// constant linear and angular velocity (of the last two samples, or fitted over
  /// fit_window_ns) up to max_extrapolation_ns, then held. Empty track: identity pose and missing_input.
  PoseQuery sample_at(TimeNs time_ns) const noexcept;

  std::size_t size() const noexcept { return samples_.size(); }
  bool degraded() const noexcept { return degraded_; }
  const PoseTrackOptions& options() const noexcept { return options_; }

 private:
  explicit PoseTrack(const PoseTrackOptions& options);
  bool is_jump(const TimedPose& from, const TimedPose& to) const noexcept;
  HealthFlags reject(HealthFlags flags) noexcept;
  void accept(const TimedPose& sample, bool restart) noexcept;
  RigidPose extrapolated(TimeNs horizon_ns) const noexcept;
  RigidPose fitted(TimeNs horizon_ns) const noexcept;

  PoseTrackOptions options_;
  HistoryRing<TimedPose> samples_;
  bool degraded_ = true;
  HealthFlags degraded_flags_;  // rejections since degraded mode began
  int consecutive_good_ = 0;
  TimedPose jump_candidate_;
  int jump_candidates_ = 0;  // consecutive rejected samples agreeing with each other
};

}  // namespace nav
