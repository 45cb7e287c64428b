// The pose track: SLERP interpolation and constant-velocity extrapolation (two samples or a
// fitted window) are exact for constant-rate motion; the fitted window divides a tracker's
// noise in the extrapolated pose; dropouts go stale, then missing, and recover when data returns;
// NaN and non-unit poses, backward clocks and single jumps are rejected and flagged, while a
// jump or a clock step that persists is re-acquired; push and sample_at never allocate and
// repeat bitwise.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <utility>
#include <vector>

#include "fusion/step_repeat.hpp"
#include "nav/fusion/pose_track.hpp"
#include "support/allocation_guard.hpp"

namespace nav {
namespace {

constexpr TimeNs kStartNs = 5 * kNsPerSecond;

/// Constant linear velocity and constant body angular velocity from a tilted start.
RigidPose constant_rate_pose(TimeNs time_ns) {
  const double t_s = static_cast<double>(time_ns - kStartNs) * 1e-9;
  const Eigen::Vector3d p0_m(0.10, -0.05, 0.20);
  const Eigen::Vector3d velocity_m_s(0.05, -0.02, 0.01);
  const Eigen::Vector3d omega_rad_s = 1.3 * Eigen::Vector3d(1.0, 2.0, -0.5).normalized();
  const Eigen::Quaterniond q0(Eigen::AngleAxisd(0.7, Eigen::Vector3d(0.3, -1.0, 0.2).normalized()));
  return {p0_m + t_s * velocity_m_s, q0 * quaternion_from_rotation_vector(t_s * omega_rad_s)};
}

double angle_between(const RigidPose& a, const RigidPose& b) {
  return relative_rotation_vector(a.rotation, b.rotation).norm();
}

PoseTrack make_track(const PoseTrackOptions& options = {}) {
  auto track = PoseTrack::create(options);
  EXPECT_TRUE(track.ok()) << track.error().describe();
  return std::move(track).value();
}

/// Pushes constant-rate samples at 1 kHz from `first_ns` (inclusive) to `last_ns` (inclusive).
void push_constant_rate(PoseTrack& track, TimeNs first_ns, TimeNs last_ns) {
  for (TimeNs t = first_ns; t <= last_ns; t += kNsPerMs) EXPECT_TRUE(track.push({t, constant_rate_pose(t)}).healthy());
}

TEST(RigidPose, ComposeAndInverseMatchEigenIsometries) {
  const RigidPose a = constant_rate_pose(kStartNs + 300 * kNsPerMs);
  const RigidPose b = constant_rate_pose(kStartNs + 900 * kNsPerMs);
  Eigen::Isometry3d ia = Eigen::Isometry3d::Identity();
  ia.linear() = a.rotation.toRotationMatrix();
  ia.translation() = a.position_m;
  Eigen::Isometry3d ib = Eigen::Isometry3d::Identity();
  ib.linear() = b.rotation.toRotationMatrix();
  ib.translation() = b.position_m;
  const Eigen::Vector3d x(0.3, -0.1, 0.7);
  const RigidPose ab = compose(a, b);
  EXPECT_LT((ab.rotation * x + ab.position_m - ia * (ib * x)).norm(), 1e-15);
  const RigidPose identity = compose(a, inverse(a));
  EXPECT_LT(identity.position_m.norm(), 1e-15);
  EXPECT_LT(angle_between(identity, RigidPose{}), 1e-15);
}

TEST(PoseTrack, InterpolationIsExactForConstantRateMotion) {
  PoseTrack track = make_track();
  TimeNs t = kStartNs;
  for (int i = 0; i < 40; ++i, t += (8 + i % 3) * kNsPerMs)
    ASSERT_TRUE(track.push({t, constant_rate_pose(t)}).healthy());
  double worst_position_m = 0.0;
  double worst_angle_rad = 0.0;
  for (TimeNs query_ns = kStartNs; query_ns < t - 10 * kNsPerMs; query_ns += 1'234'567) {
    const PoseQuery query = track.sample_at(query_ns);
    ASSERT_TRUE(query.flags.healthy());
    ASSERT_FALSE(query.degraded);
    ASSERT_FALSE(query.extrapolated);
    worst_position_m =
        std::max(worst_position_m, (query.pose.position_m - constant_rate_pose(query_ns).position_m).norm());
    worst_angle_rad = std::max(worst_angle_rad, angle_between(query.pose, constant_rate_pose(query_ns)));
  }
  std::printf("interpolation: worst position error %.3g m, worst angle error %.3g rad\n", worst_position_m,
              worst_angle_rad);
  EXPECT_LT(worst_position_m, 1e-12);
  EXPECT_LT(worst_angle_rad, 1e-12);
}

TEST(PoseTrack, ExtrapolationIsExactUpToTheHorizonThenHolds) {
  PoseTrackOptions options;
  options.max_extrapolation_ns = 30 * kNsPerMs;
  options.max_age_ns = 50 * kNsPerMs;
  PoseTrack track = make_track(options);
  const TimeNs newest_ns = kStartNs + 100 * kNsPerMs;
  push_constant_rate(track, kStartNs, newest_ns);
  for (TimeNs ahead_ns : {TimeNs{1}, 5 * kNsPerMs, 20 * kNsPerMs, 30 * kNsPerMs}) {
    const PoseQuery query = track.sample_at(newest_ns + ahead_ns);
    EXPECT_TRUE(query.extrapolated);
    EXPECT_TRUE(query.flags.healthy());
    EXPECT_FALSE(query.degraded);
    EXPECT_EQ(query.age_ns, ahead_ns);
    EXPECT_LT((query.pose.position_m - constant_rate_pose(newest_ns + ahead_ns).position_m).norm(), 1e-12);
    EXPECT_LT(angle_between(query.pose, constant_rate_pose(newest_ns + ahead_ns)), 1e-12);
  }
  const PoseQuery held = track.sample_at(newest_ns + 45 * kNsPerMs);
  EXPECT_TRUE(held.flags.has(HealthFlag::stale_input));
  EXPECT_TRUE(held.degraded);
  EXPECT_LT((held.pose.position_m - constant_rate_pose(newest_ns + 30 * kNsPerMs).position_m).norm(), 1e-12);
  EXPECT_LT(angle_between(held.pose, constant_rate_pose(newest_ns + 30 * kNsPerMs)), 1e-12);
}

TEST(PoseTrack, EmptyTrackIsMissingAndDegraded) {
  const PoseTrack track = make_track();
  const PoseQuery query = track.sample_at(kStartNs);
  EXPECT_TRUE(query.flags.has(HealthFlag::missing_input));
  EXPECT_TRUE(query.degraded);
  EXPECT_EQ(query.pose.position_m, Eigen::Vector3d::Zero());
}

TEST(PoseTrack, DropoutGoesStaleThenMissingAndRecoversWhenDataReturns) {
  PoseTrack track = make_track();  // max_age 50 ms, missing after 500 ms, recovery after 3 samples
  const TimeNs last_ns = kStartNs + 100 * kNsPerMs;
  push_constant_rate(track, kStartNs, last_ns);
  EXPECT_FALSE(track.sample_at(last_ns + 10 * kNsPerMs).degraded);
  const PoseQuery stale = track.sample_at(last_ns + 60 * kNsPerMs);
  EXPECT_TRUE(stale.flags.has(HealthFlag::stale_input));
  EXPECT_FALSE(stale.flags.has(HealthFlag::missing_input));
  EXPECT_TRUE(stale.degraded);
  const PoseQuery missing = track.sample_at(last_ns + 600 * kNsPerMs);
  EXPECT_TRUE(missing.flags.has(HealthFlag::missing_input));
  EXPECT_TRUE(missing.degraded);
  EXPECT_TRUE(missing.pose.position_m.allFinite());  // the held pose, never garbage

  const TimeNs back_ns = last_ns + kNsPerSecond;
  for (int i = 0; i < 3; ++i) {
    const TimeNs t = back_ns + i * kNsPerMs;
    EXPECT_TRUE(track.push({t, constant_rate_pose(t)}).healthy());
    const PoseQuery query = track.sample_at(t);
    EXPECT_EQ(query.degraded, i < 2) << "sample " << i;  // degraded until 3 good samples
    EXPECT_LT((query.pose.position_m - constant_rate_pose(t).position_m).norm(), 1e-12);
  }
  EXPECT_EQ(track.size(), 3u);  // the track restarted: nothing interpolates across the gap
  const PoseQuery recovered = track.sample_at(back_ns + 5 * kNsPerMs);
  EXPECT_TRUE(recovered.flags.healthy());
  EXPECT_LT((recovered.pose.position_m - constant_rate_pose(back_ns + 5 * kNsPerMs).position_m).norm(), 1e-12);
}

TEST(PoseTrack, NanAndNonUnitPosesAreRejected) {
  PoseTrack track = make_track();
  const TimeNs last_ns = kStartNs + 20 * kNsPerMs;
  push_constant_rate(track, kStartNs, last_ns);
  const PoseQuery before = track.sample_at(last_ns + 3 * kNsPerMs);

  RigidPose nan_pose = constant_rate_pose(last_ns + kNsPerMs);
  nan_pose.position_m.y() = std::numeric_limits<double>::quiet_NaN();
  EXPECT_TRUE(track.push({last_ns + kNsPerMs, nan_pose}).has(HealthFlag::bad_sample));
  RigidPose not_unit = constant_rate_pose(last_ns + 2 * kNsPerMs);
  not_unit.rotation.coeffs() *= 1.1;
  EXPECT_TRUE(track.push({last_ns + 2 * kNsPerMs, not_unit}).has(HealthFlag::bad_sample));

  const PoseQuery after = track.sample_at(last_ns + 3 * kNsPerMs);
  EXPECT_EQ(after.pose.position_m, before.pose.position_m);  // the bad samples left no trace
  EXPECT_TRUE(after.flags.has(HealthFlag::bad_sample));
  EXPECT_TRUE(after.degraded);
  push_constant_rate(track, last_ns + 3 * kNsPerMs, last_ns + 5 * kNsPerMs);
  const PoseQuery recovered = track.sample_at(last_ns + 5 * kNsPerMs);
  EXPECT_TRUE(recovered.flags.healthy());
  EXPECT_FALSE(recovered.degraded);
}

TEST(PoseTrack, ClockGoingBackwardsIsRejected) {
  PoseTrack track = make_track();
  const TimeNs last_ns = kStartNs + 20 * kNsPerMs;
  push_constant_rate(track, kStartNs, last_ns);
  const std::size_t size = track.size();
  EXPECT_TRUE(track.push({last_ns - 5 * kNsPerMs, constant_rate_pose(last_ns)}).has(HealthFlag::clock_went_backwards));
  EXPECT_TRUE(track.push({last_ns, constant_rate_pose(last_ns)}).has(HealthFlag::clock_went_backwards));
  EXPECT_EQ(track.size(), size);
  const PoseQuery query = track.sample_at(last_ns);
  EXPECT_TRUE(query.flags.has(HealthFlag::clock_went_backwards));
  EXPECT_TRUE(query.degraded);
  EXPECT_LT((query.pose.position_m - constant_rate_pose(last_ns).position_m).norm(), 1e-12);
  push_constant_rate(track, last_ns + kNsPerMs, last_ns + 3 * kNsPerMs);
  EXPECT_FALSE(track.sample_at(last_ns + 3 * kNsPerMs).degraded);
}

TEST(PoseTrack, SingleJumpIsRejected) {
  PoseTrack track = make_track();
  const TimeNs last_ns = kStartNs + 20 * kNsPerMs;
  push_constant_rate(track, kStartNs, last_ns);
  RigidPose outlier = constant_rate_pose(last_ns + kNsPerMs);
  outlier.position_m.x() += 0.10;  // 10 cm in 1 ms
  EXPECT_TRUE(track.push({last_ns + kNsPerMs, outlier}).has(HealthFlag::pose_jump_rejected));
  RigidPose flipped = constant_rate_pose(last_ns + 2 * kNsPerMs);
  flipped.rotation = flipped.rotation * Eigen::Quaterniond(Eigen::AngleAxisd(1.0, Eigen::Vector3d::UnitX()));
  EXPECT_TRUE(track.push({last_ns + 2 * kNsPerMs, flipped}).has(HealthFlag::pose_jump_rejected));
  EXPECT_TRUE(track.sample_at(last_ns + 2 * kNsPerMs).flags.has(HealthFlag::pose_jump_rejected));
  push_constant_rate(track, last_ns + 3 * kNsPerMs, last_ns + 5 * kNsPerMs);
  for (TimeNs t = last_ns; t <= last_ns + 5 * kNsPerMs; t += kNsPerMs / 4) {
    const PoseQuery query = track.sample_at(t);
    EXPECT_LT((query.pose.position_m - constant_rate_pose(t).position_m).norm(), 1e-12);
    EXPECT_LT(angle_between(query.pose, constant_rate_pose(t)), 1e-12);
  }
  EXPECT_TRUE(track.sample_at(last_ns + 5 * kNsPerMs).flags.healthy());
}

TEST(PoseTrack, PersistentJumpIsReacquired) {
  PoseTrackOptions options;
  options.jump_confirmations = 3;
  PoseTrack track = make_track(options);
  const TimeNs last_ns = kStartNs + 20 * kNsPerMs;
  push_constant_rate(track, kStartNs, last_ns);
  const Eigen::Vector3d offset_m(0.0, 0.12, 0.0);  // the reference frame was bumped 12 cm
  auto moved = [&](TimeNs t) {
    const RigidPose pose = constant_rate_pose(t);
    return TimedPose{t, {pose.position_m + offset_m, pose.rotation}};
  };
  EXPECT_TRUE(track.push(moved(last_ns + 1 * kNsPerMs)).has(HealthFlag::pose_jump_rejected));
  EXPECT_TRUE(track.push(moved(last_ns + 2 * kNsPerMs)).has(HealthFlag::pose_jump_rejected));
  EXPECT_TRUE(track.push(moved(last_ns + 3 * kNsPerMs)).healthy());  // third agreeing sample: re-acquired
  EXPECT_TRUE(track.sample_at(last_ns + 3 * kNsPerMs).degraded);
  for (int i = 4; i <= 6; ++i) EXPECT_TRUE(track.push(moved(last_ns + i * kNsPerMs)).healthy());
  const PoseQuery query = track.sample_at(last_ns + 6 * kNsPerMs + 500'000);
  EXPECT_FALSE(query.degraded);
  EXPECT_TRUE(query.flags.healthy());
  EXPECT_LT((query.pose.position_m - moved(last_ns + 6 * kNsPerMs + 500'000).pose.position_m).norm(), 1e-12);
}

TEST(PoseTrack, PersistentClockStepBackIsReacquired) {
  PoseTrack track = make_track();
  const TimeNs last_ns = kStartNs + 20 * kNsPerMs;
  push_constant_rate(track, kStartNs, last_ns);
  const TimeNs back_ns = last_ns - 2 * kNsPerSecond;  // the time stamps stepped 2 s back and go on from there
  for (int i = 0; i < 2; ++i) {
    const TimeNs t = back_ns + i * kNsPerMs;
    EXPECT_TRUE(
        track.push({t, constant_rate_pose(last_ns + (i + 1) * kNsPerMs)}).has(HealthFlag::clock_went_backwards));
  }
  EXPECT_TRUE(track.push({back_ns + 2 * kNsPerMs, constant_rate_pose(last_ns + 3 * kNsPerMs)}).healthy());
  EXPECT_EQ(track.size(), 1u);
  const Eigen::Vector3d reacquired_m = track.sample_at(back_ns + 2 * kNsPerMs).pose.position_m;
  EXPECT_LT((reacquired_m - constant_rate_pose(last_ns + 3 * kNsPerMs).position_m).norm(), 1e-12);
}

TEST(PoseTrack, RingKeepsTheNewestSamples) {
  PoseTrackOptions options;
  options.capacity = 16;
  PoseTrack track = make_track(options);
  const TimeNs last_ns = kStartNs + 999 * kNsPerMs;
  push_constant_rate(track, kStartNs, last_ns);
  EXPECT_EQ(track.size(), 16u);
  const TimeNs oldest_ns = last_ns - 15 * kNsPerMs;
  const PoseQuery inside = track.sample_at(oldest_ns + 7'500'000);
  EXPECT_TRUE(inside.flags.healthy());
  EXPECT_LT((inside.pose.position_m - constant_rate_pose(oldest_ns + 7'500'000).position_m).norm(), 1e-12);
  const PoseQuery too_old = track.sample_at(oldest_ns - kNsPerMs);
  EXPECT_TRUE(too_old.flags.has(HealthFlag::stale_input));
  EXPECT_LT((too_old.pose.position_m - constant_rate_pose(oldest_ns).position_m).norm(), 1e-12);
}

TEST(PoseTrack, ItsHealthFlagsHaveNames) {
  EXPECT_STREQ(health_flag_name(HealthFlag::clock_went_backwards), "clock_went_backwards");
  EXPECT_STREQ(health_flag_name(HealthFlag::pose_jump_rejected), "pose_jump_rejected");
}

/// The constant-rate pose at `time_ns` with Gaussian position and rotation noise per axis.
RigidPose noisy_pose(TimeNs time_ns, std::mt19937_64& random, double position_std_m, double rotation_std_rad) {
  std::normal_distribution<double> unit(0.0, 1.0);
  RigidPose pose = constant_rate_pose(time_ns);
  const double x = unit(random), y = unit(random), z = unit(random);
  const double a = unit(random), b = unit(random), c = unit(random);
  pose.position_m += position_std_m * Eigen::Vector3d(x, y, z);
  pose.rotation = pose.rotation * quaternion_from_rotation_vector(rotation_std_rad * Eigen::Vector3d(a, b, c));
  return pose;
}

constexpr TimeNs kTrackerPeriodNs = 16'666'667;  // 60 Hz

TEST(PoseTrack, FittedExtrapolationIsExactForConstantRateMotion) {
  PoseTrackOptions options;
  options.fit_window_ns = 100 * kNsPerMs;
  PoseTrack track = make_track(options);
  for (int i = 0; i < 30; ++i) {
    const TimeNs t = kStartNs + i * kTrackerPeriodNs;
    ASSERT_TRUE(track.push({t, constant_rate_pose(t)}).healthy());
  }
  const TimeNs newest_ns = kStartNs + 29 * kTrackerPeriodNs;
  for (TimeNs ahead_ns : {TimeNs{1}, 10 * kNsPerMs, 26 * kNsPerMs}) {
    const PoseQuery query = track.sample_at(newest_ns + ahead_ns);
    EXPECT_TRUE(query.extrapolated);
    EXPECT_LT((query.pose.position_m - constant_rate_pose(newest_ns + ahead_ns).position_m).norm(), 1e-12);
    EXPECT_LT(angle_between(query.pose, constant_rate_pose(newest_ns + ahead_ns)), 1e-12);
  }
}

/// RMS position and angle errors of the pose extrapolated 10 to 26 ms past each sample of a
/// 60 Hz tracker with 0.25 mm and 1 mrad noise per axis (the demo's), over 600 samples.
std::pair<double, double> extrapolation_errors(TimeNs fit_window_ns) {
  PoseTrackOptions options;
  options.fit_window_ns = fit_window_ns;
  PoseTrack track = make_track(options);
  std::mt19937_64 random(5);
  double position2 = 0.0, angle2 = 0.0;
  int count = 0;
  for (int i = 0; i < 600; ++i) {
    const TimeNs t = kStartNs + i * kTrackerPeriodNs;
    EXPECT_TRUE(track.push({t, noisy_pose(t, random, 0.25e-3, 1e-3)}).healthy());
    if (i < 12) continue;
    for (TimeNs ahead_ns = 10 * kNsPerMs; ahead_ns <= 26 * kNsPerMs; ahead_ns += 4 * kNsPerMs) {
      const PoseQuery query = track.sample_at(t + ahead_ns);
      position2 += (query.pose.position_m - constant_rate_pose(t + ahead_ns).position_m).squaredNorm();
      angle2 += std::pow(angle_between(query.pose, constant_rate_pose(t + ahead_ns)), 2);
      ++count;
    }
  }
  return {std::sqrt(position2 / count), std::sqrt(angle2 / count)};
}

TEST(PoseTrack, AFittedWindowDividesTheTrackersNoiseInTheExtrapolatedPose) {
  const auto [two_m, two_rad] = extrapolation_errors(0);
  const auto [fitted_m, fitted_rad] = extrapolation_errors(100 * kNsPerMs);
  std::printf(
      "extrapolated 10-26 ms past a 60 Hz tracker (0.25 mm, 1 mrad): last two samples %.3f mm, %.3f mrad; fitted "
      "over 100 ms %.3f mm, %.3f mrad\n",
      1e3 * two_m, 1e3 * two_rad, 1e3 * fitted_m, 1e3 * fitted_rad);
  // Two samples multiply the noise by about 2.6 at these horizons; six fitted ones by about 1.
  EXPECT_GT(two_m, 2.0 * 0.25e-3 * std::sqrt(3.0));
  EXPECT_LT(fitted_m, 0.5 * two_m);
  EXPECT_LT(fitted_rad, 0.5 * two_rad);
}

TEST(PoseTrack, BadOptionsNameTheirField) {
  PoseTrackOptions options;
  options.missing_after_ns = options.max_age_ns - 1;
  auto track = PoseTrack::create(options);
  ASSERT_FALSE(track.ok());
  EXPECT_EQ(track.error().field, "pose_track.missing_after_ns");
  options = {};
  options.capacity = 1;
  EXPECT_EQ(PoseTrack::create(options).error().field, "pose_track.capacity");
  options = {};
  options.fit_window_ns = -1;
  EXPECT_EQ(PoseTrack::create(options).error().field, "pose_track.fit_window_ns");
}

/// A noisy 1 kHz stream with a dropout, a NaN, a backward timestamp, an outlier and a
/// persistent jump; every push and a 1 kHz query offset by 0.4 ms. Returns every output
/// bit, and counts allocations.
std::vector<double> scripted_track_run(std::size_t* allocations) {
  PoseTrackOptions options;
  options.fit_window_ns = 5 * kNsPerMs;  // the fitted extrapolation
  PoseTrack track = make_track(options);
  std::mt19937_64 random(42);
  std::normal_distribution<double> noise_m(0.0, 0.25e-3);
  std::vector<double> outputs;
  outputs.reserve(4000 * 10);
  std::size_t allocated = 0;
  for (int i = 0; i < 4000; ++i) {
    const TimeNs t = kStartNs + i * kNsPerMs;
    TimedPose sample{t, constant_rate_pose(t)};
    sample.pose.position_m += Eigen::Vector3d(noise_m(random), noise_m(random), noise_m(random));
    if (i == 700) sample.pose.rotation.w() = std::numeric_limits<double>::quiet_NaN();
    if (i == 900) sample.time_ns -= 3 * kNsPerMs;
    if (i == 1200) sample.pose.position_m.z() += 0.2;
    if (i >= 3000) sample.pose.position_m.x() += 0.1;
    const bool dropped = i >= 2000 && i < 2300;
    PoseQuery query;
    HealthFlags flags;
    {
      testing::AllocationGuard guard;
      if (!dropped) flags = track.push(sample);
      query = track.sample_at(t + 400'000);
      allocated += guard.allocations();
    }
    outputs.push_back(static_cast<double>(flags.bits() | (query.flags.bits() << 16)));
    outputs.push_back(query.degraded ? 1.0 : 0.0);
    for (int k = 0; k < 3; ++k) outputs.push_back(query.pose.position_m[k]);
    for (int k = 0; k < 4; ++k) outputs.push_back(query.pose.rotation.coeffs()[k]);
  }
  *allocations = allocated;
  return outputs;
}

TEST(PoseTrack, StepsNeverAllocateAndRepeatBitwise) {
  const std::vector<double> first = testing::expect_allocation_free_and_repeatable(scripted_track_run);
  ASSERT_EQ(first.size(), 4000u * 9u);
  // The script's faults were all seen, each at its tick, and the track ends healthy.
  constexpr std::size_t kPerTick = 9;
  auto push_flags = [&](std::size_t tick) { return static_cast<std::uint32_t>(first[tick * kPerTick]) & 0xffffu; };
  auto query_flags = [&](std::size_t tick) { return static_cast<std::uint32_t>(first[tick * kPerTick]) >> 16; };
  EXPECT_EQ(push_flags(700), static_cast<std::uint32_t>(HealthFlag::bad_sample));
  EXPECT_EQ(push_flags(900), static_cast<std::uint32_t>(HealthFlag::clock_went_backwards));
  EXPECT_EQ(push_flags(1200), static_cast<std::uint32_t>(HealthFlag::pose_jump_rejected));
  EXPECT_EQ(push_flags(1201), 0u);
  EXPECT_NE(query_flags(2100) & static_cast<std::uint32_t>(HealthFlag::stale_input), 0u);
  EXPECT_EQ(push_flags(3001), static_cast<std::uint32_t>(HealthFlag::pose_jump_rejected));
  EXPECT_EQ(push_flags(3002), 0u);             // re-acquired
  EXPECT_EQ(first[1500 * kPerTick + 1], 0.0);  // not degraded between faults
  EXPECT_EQ(first[2100 * kPerTick + 1], 1.0);  // degraded in the dropout
  EXPECT_EQ(first[first.size() - kPerTick], 0.0);
  EXPECT_EQ(first[first.size() - kPerTick + 1], 0.0);
}

}  // namespace
}  // namespace nav
