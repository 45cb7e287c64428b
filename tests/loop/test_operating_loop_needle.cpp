// The operating loop stepping the flexible needle coupled to its reduced liver, on a simulated
// clock at 1 kHz: an 8 x 2 x 2 cm beam of 10 kPa held at x = 0 whose x = 8 cm face is the
// diaphragm (breathing from a respiratory marker), a 12-mode linear reduced model stepped
// every 10 ticks, and a 15 cm needle tracked at 250 Hz (2 ms delivery delay) that is pushed
// down at 20 mm/s into the beam's top face over the tumour (the beam's centre node).
// Checked: the loop's needle and liver equal, bitwise, the stand-alone coupled needle stepped
// with the same base poses and diaphragm; the push deforms the liver (the tumour estimate
// moves down against the same loop without the needle), the tip force resists the insertion
// and the capsule is punctured once; push and tick never allocate and repeat bitwise, also
// with a moved copy of the model; a lost or NaN needle pose holds the base, flags, stays
// finite and recovers (a far re-acquisition glides, flagged); bad needle declarations are
// refused by field.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <vector>

#include "loop/loop_beam_support.hpp"
#include "nav/core/clock.hpp"
#include "nav/loop/operating_loop.hpp"
#include "nav/needle/coupled_needle_step.hpp"
#include "nav/reduced/reduction.hpp"
#include "needle/needle_coupling_support.hpp"
#include "support/allocation_guard.hpp"
#include "tissue/tissue_test_support.hpp"

namespace nav {
namespace {

constexpr int kTissueEvery = 10;  // 100 Hz liver steps on the 1 kHz tick
constexpr double kStepS = 0.01;
constexpr TimeNs kTick = kNsPerMs, kLatency = 50 * kNsPerMs;
constexpr double kTopM = 0.02;
constexpr double kMarkerMeanM = 0.1, kMarkerAmplitudeM = 0.002, kBreathingPeriodS = 2.0;
const Eigen::Vector3d kDiaphragmPerMarker{0.0, 0.0, 0.5};
constexpr TimeNs kPushFrom = 100 * kNsPerMs;  // the tip starts 5 mm above the top face
constexpr double kPushSpeedMPerS = 0.02, kPushTravelM = 0.016;
constexpr TimeNs kPoseEvery = 4 * kNsPerMs, kPoseDelay = 2 * kNsPerMs;
constexpr TimeNs kMarkerEvery = 25 * kNsPerMs, kMarkerDelay = 5 * kNsPerMs;

/// The needle base in the marker frame: 1 cm below the marker, the needle pointing down
/// (its +x along the marker's -z).
RigidPose marker_from_base() {
  return {{0.0, 0.0, -0.01}, Eigen::Quaterniond(Eigen::AngleAxisd(0.5 * std::numbers::pi, Eigen::Vector3d::UnitY()))};
}

/// The loop with and without the needle on one reduced beam, built once per process.
struct LoopSetup {
  TetMesh mesh = testing::box_mesh({0.08, 0.02, kTopM}, 0.01);
  TissueScene scene;
  std::int32_t tumour = 0;
  RigidPose registration;  // model_from_tracker
  OperatingLoopNeedleOptions needle;
  OperatingLoopModel with_needle, without_needle;
  LoopSetup() {
    scene.default_material = {10.0e3, 0.3, 1000.0};
    scene.gravity_m_s2 = {0.0, 0.0, 0.0};
    scene.fixed_nodes = testing::nodes_where(mesh, 0, 0.0);
    scene.prescribed_nodes = testing::nodes_where(mesh, 0, 0.08);
    scene.max_point_forces = 32;
    tumour = testing::nearest_node(mesh, {0.04, 0.01, 0.01});
    const TissueSolverOptions solver{.rotation = ElementRotation::none,
                                     .integrator = Integrator::quasi_static,
                                     .step_s = kStepS,
                                     .cg_iterations = 1};
    const ReductionOptions reduction{
        .source = ReducedBasisSource::linear_modes, .force_kind = ReducedForceKind::linear, .basis_size = 12};
    const ReducedBasis basis = make_modal_basis(mesh, scene, solver, reduction).value();
    ReducedSolverOptions reduced_options;
    reduced_options.integrator = ReducedIntegrator::quasi_static;
    reduced_options.step_s = kStepS;
    const ReducedModel reduced = make_reduced_model(mesh, scene, solver, basis, reduced_options).value();
    ReducedKalmanOptions filter_options;
    filter_options.correction_std.assign(12, 1e-4);
    filter_options.correlation_time_s = 2.0;
    const ObservedPoint points[] = {observed_node(tumour)};
    const ReducedKalmanModel filter = make_reduced_kalman_model(mesh, basis, reduced, points, filter_options).value();

    registration = {{0.01, -0.02, 0.03}, Eigen::Quaterniond(Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitZ()))};
    OperatingLoopOptions o;
    o.model_from_tracker = registration;
    o.tick_period_ns = kTick;
    o.display_latency_ns = kLatency;
    o.tissue_every_ticks = kTissueEvery;
    o.needle_tip_in_marker_m = {0.0, 0.0, -0.16};  // the rigid tip of the same needle
    o.needle.max_extrapolation_ns = 100 * kNsPerMs;
    o.diaphragm_per_marker = kDiaphragmPerMarker;
    o.respiratory_reference_m = kMarkerMeanM;
    needle.scene = testing::top_face_layer(0.04, 0.01, kTopM, 0.003);
    needle.marker_from_base = marker_from_base();
    needle.parameters.max_pose_jump_m = 0.005;
    auto built = make_operating_loop_model(reduced, filter, o, needle, mesh);
    EXPECT_TRUE(built.ok()) << built.error().describe();
    with_needle = std::move(built).value();
    without_needle = make_operating_loop_model(reduced, filter, o).value();
  }
};

const LoopSetup& setup() {
  static const LoopSetup s;
  return s;
}

/// The true needle base (model frame) at time t: over the tumour, lowered from kPushFrom.
RigidPose true_base(TimeNs t) {
  const double lowered_m = std::clamp(kPushSpeedMPerS * 1e-9 * static_cast<double>(t - kPushFrom), 0.0, kPushTravelM);
  const NeedlePose p = testing::needle_above(0.04, 0.01, kTopM, lowered_m);
  return {{p.position_m[0], p.position_m[1], p.position_m[2]},
          Eigen::Quaterniond(p.rotation_wxyz[0], p.rotation_wxyz[1], p.rotation_wxyz[2], p.rotation_wxyz[3])};
}

double marker_m(TimeNs t) {
  return kMarkerMeanM +
         kMarkerAmplitudeM * std::sin(2.0 * std::numbers::pi * 1e-9 * static_cast<double>(t) / kBreathingPeriodS);
}

/// What a run changes from the nominal push (times in ns; -1: not used).
struct Script {
  bool needle = true;  // the loop with the needle model, or the one without
  TimeNs duration_ns = kNsPerSecond;
  TimeNs gap_from = -1, gap_to = -1;  // no needle pose measured in between
  TimeNs nan_at = -1;                 // the needle pose measured then is NaN
};

struct ScriptedRun {
  std::vector<OperatingLoopOutputs> ticks;
  std::size_t allocations = 0;
};

/// The scripted run; only the loop's calls are inside the allocation guard.
ScriptedRun run(const Script& script, const OperatingLoopModel* model_override = nullptr) {
  const LoopSetup& s = setup();
  const OperatingLoopModel& model = model_override != nullptr ? *model_override
                                    : script.needle           ? s.with_needle
                                                              : s.without_needle;
  OperatingLoopData data = make_operating_loop_data(model).value();
  ScriptedRun out;
  out.ticks.reserve(static_cast<std::size_t>(script.duration_ns / kTick) + 1);
  const RigidPose tracker_from_model = inverse(s.registration), base_from_marker = inverse(marker_from_base());
  TimeNs next_pose = 0, next_marker = 0;
  testing::AllocationGuard guard;
  for (TimeNs now = 0; now <= script.duration_ns; now += kTick) {
    for (; next_pose + kPoseDelay <= now; next_pose += kPoseEvery) {
      if (script.gap_from >= 0 && next_pose >= script.gap_from && next_pose < script.gap_to) continue;
      RigidPose marker = compose(tracker_from_model, compose(true_base(next_pose), base_from_marker));
      if (next_pose == script.nan_at) marker.position_m[2] = std::numeric_limits<double>::quiet_NaN();
      push_needle_pose(model, data, {next_pose, marker});
    }
    for (; next_marker + kMarkerDelay <= now; next_marker += kMarkerEvery)
      push_respiratory_sample(model, data, next_marker, {0.0, 0.0, marker_m(next_marker)});
    tick(model, data, now);
    out.ticks.push_back(data.outputs);
  }
  out.allocations = guard.allocations();
  return out;
}

std::size_t at(TimeNs t) { return static_cast<std::size_t>(t / kTick); }
double distance_m(const Point3& a, const Eigen::Vector3d& b) {
  return std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]);
}
/// Whether t is within 10 ms after the push starts or stops (where extrapolation lags).
bool after_a_kink(TimeNs t) {
  const auto stop = kPushFrom + static_cast<TimeNs>(kPushTravelM / kPushSpeedMPerS * 1e9);
  return (t >= kPushFrom && t < kPushFrom + 10 * kNsPerMs) || (t >= stop && t < stop + 10 * kNsPerMs);
}

/// How far the published needle base is from the true one at t.
double base_error_m(const OperatingLoopOutputs& o, TimeNs t) {
  return (o.needle_shape.base_pose.position_m - true_base(t).position_m).norm();
}
bool finite(const Point3& p) { return std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]); }

/// The first tick whose needle model steps.
std::size_t first_needle_tick(const ScriptedRun& r) {
  std::size_t k = 0;
  while (k < r.ticks.size() && r.ticks[k].needle_shape.node_count == 0) ++k;
  return k;
}

TEST(OperatingLoopNeedle, EqualsTheStandaloneCoupledNeedleBitwise) {
  const LoopSetup& s = setup();
  const ScriptedRun r = run({});
  const std::size_t first = first_needle_tick(r);
  ASSERT_LT(first, 20u);
  // The independent reference: the stand-alone coupled needle on the same reduced liver,
  // stepped with the base poses the loop published and, every 10th tick, the diaphragm it used.
  const ReducedCoupledNeedleModel reference =
      make_coupled_needle_model(s.needle.parameters, s.needle.scene, s.with_needle.rungs[0].reduced, s.mesh,
                                s.needle.max_point_forces, kTissueEvery)
          .value();
  ReducedCoupledNeedleData data =
      make_coupled_needle_data(reference, to_needle_pose(r.ticks[first].needle_shape.base_pose)).value();
  int node_mismatches = 0, q_mismatches = 0, compared_steps = 0;
  double worst_base_m = 0.0;
  for (std::size_t k = 0; k < r.ticks.size(); ++k) {
    const OperatingLoopOutputs& o = r.ticks[k];
    if (k >= first) {
      NeedleInputs inputs;
      inputs.base = to_needle_pose(o.needle_shape.base_pose);
      step_needle(reference, data, inputs);
    }
    if (k % kTissueEvery == 0) {
      TissueInputs inputs;
      inputs.prescribed_displacement_m = o.diaphragm_m;
      step_tissue(reference, data, inputs);
      for (std::size_t j = 0; j < data.tissue.q.size(); ++j)
        q_mismatches += o.liver_q[j] != data.tissue.q[j];  // no observation: dq = 0
      ++compared_steps;
    }
    if (k < first) continue;
    ASSERT_EQ(o.needle_shape.node_count, reference.interaction.needle.node_count());
    for (int n = 0; n < o.needle_shape.node_count; ++n)
      for (std::size_t c = 0; c < 3; ++c)
        node_mismatches += o.needle_shape.centreline_m[static_cast<std::size_t>(n)][c] !=
                           data.interaction.needle.positions_m[3 * static_cast<std::size_t>(n) + c];
    ASSERT_EQ(o.needle_shape.punctures, data.interaction.report.punctures) << k;
    // The published base is the tracked marker (extrapolated over the 2 to 5 ms since the
    // newest sample, exact for constant velocity) times marker_from_base.
    const TimeNs t = static_cast<TimeNs>(k) * kTick;
    if (k >= first + 20 && !after_a_kink(t)) worst_base_m = std::max(worst_base_m, base_error_m(o, t));
  }
  std::printf(
      "%d liver steps compared; the needle punctured %d time(s); published base within %.2e m of the tracked one\n",
      compared_steps, r.ticks.back().needle_shape.punctures, worst_base_m);
  EXPECT_EQ(r.ticks.back().needle_shape.punctures, 1);  // the comparison covers the puncture
  EXPECT_EQ(node_mismatches, 0);
  EXPECT_EQ(q_mismatches, 0);
  EXPECT_LT(worst_base_m, 1e-9);  // constant-velocity extrapolation is exact up to rounding
}

TEST(OperatingLoopNeedle, PushingTheNeedleDeformsTheLiverAndResists) {
  const ScriptedRun with = run({});
  Script rigid;
  rigid.needle = false;
  const ScriptedRun without = run(rigid);
  const OperatingLoopOutputs& end = with.ticks.back();
  const OperatingLoopOutputs& end_rigid = without.ticks.back();
  const double moved_down_m = end_rigid.tumour_now_m[2] - end.tumour_now_m[2];
  const double moved_sideways_m =
      std::hypot(end_rigid.tumour_now_m[0] - end.tumour_now_m[0], end_rigid.tumour_now_m[1] - end.tumour_now_m[1]);
  double largest_resisting_n = 0.0, most_pushing_n = 0.0;
  int flagged_ticks = 0;
  const OperatingLoopOutputs* largest = &with.ticks.front();
  for (const OperatingLoopOutputs& o : with.ticks) {
    flagged_ticks += o.needle_shape.flags.healthy() ? 0 : 1;
    if (o.needle_shape.tip_force_n[2] > largest_resisting_n) largest = &o;
    largest_resisting_n = std::max(largest_resisting_n, o.needle_shape.tip_force_n[2]);  // insertion is -z
    most_pushing_n = std::min(most_pushing_n, o.needle_shape.tip_force_n[2]);
  }
  // Before the puncture only the capsule's contact holds the needle: the holder feels the tip's
  // force (up to the needle's inertia and damping over 1 ms steps).
  const double holder_at_largest_n = largest->needle_shape.base_force_n[2];
  std::printf(
      "tumour estimate moved %.3f mm down (%.3f mm sideways, %.3f mm down at now + latency) by the needle; largest tip "
      "force "
      "against the insertion %.3f N; tip depth %.2f mm; holder force then %.3f N, at the end (%.3f, %.3f, %.3f) N; "
      "ticks with needle flags %d\n",
      1e3 * moved_down_m, 1e3 * moved_sideways_m, 1e3 * (end_rigid.tumour_ahead_m[2] - end.tumour_ahead_m[2]),
      largest_resisting_n, 1e3 * end.needle_shape.tip_depth_m, holder_at_largest_n, end.needle_shape.base_force_n[0],
      end.needle_shape.base_force_n[1], end.needle_shape.base_force_n[2], flagged_ticks);
  EXPECT_EQ(flagged_ticks, 0);  // a nominal insertion: no refused pose, the solver within its bound
  EXPECT_GT(moved_down_m, 1e-4);
  EXPECT_LT(moved_sideways_m, 0.2 * moved_down_m);
  // The look-ahead carries the needle's forces: the tumour ahead stays pushed down (the
  // quasi-static liver would spring back within one step without them).
  const double ahead_down_m = end_rigid.tumour_ahead_m[2] - end.tumour_ahead_m[2];
  EXPECT_NEAR(ahead_down_m, moved_down_m, 0.1 * moved_down_m);
  EXPECT_GT(largest_resisting_n, 0.1);  // the capsule holds up to f_p = 0.2 N
  EXPECT_LE(largest_resisting_n, 0.2 + 1e-6);
  EXPECT_GE(most_pushing_n, -1e-9);  // the tissue never pulls the tip in
  EXPECT_NEAR(holder_at_largest_n, largest_resisting_n, 0.05 * largest_resisting_n);
  EXPECT_GT(end.needle_shape.base_force_n[2], 0.0);  // inserted: cutting and friction still resist
  EXPECT_EQ(end.needle_shape.punctures, 1);
  EXPECT_GT(end.needle_shape.tip_depth_m, 0.005);
  EXPECT_EQ(end_rigid.needle_shape.node_count, 0);
  // The published tip is the modelled one, and the distance to the tumour uses it.
  EXPECT_EQ(end.needle_tip_m, end.needle_shape.centreline_m[static_cast<std::size_t>(end.needle_shape.node_count - 1)]);
  const Eigen::Vector3d tip(end.needle_tip_m[0], end.needle_tip_m[1], end.needle_tip_m[2]);
  EXPECT_EQ(end.tip_to_tumour_m, distance_m(end.tumour_now_m, tip));
  // Held still at the end, the needle's bend carries over to the tip ahead unchanged.
  const Eigen::Vector3d bend =
      tip - Eigen::Vector3d(end_rigid.needle_tip_m[0], end_rigid.needle_tip_m[1], end_rigid.needle_tip_m[2]);
  EXPECT_LT(distance_m(end.needle_tip_ahead_m,
                       Eigen::Vector3d(end_rigid.needle_tip_ahead_m[0], end_rigid.needle_tip_ahead_m[1],
                                       end_rigid.needle_tip_ahead_m[2]) +
                           bend),
            1e-12);
}

/// |a - b| of two forces.
double change_n(const Point3& a, const Point3& b) { return std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]); }

// The needle's forces come out of every 1 kHz tick (nav/needle_force), the liver under them only
// every 10th: at a liver step the tip and holder forces must not jump by more than they change
// from tick to tick between liver steps (the largest such change in the liver periods before and
// after it, with a 5 % margin), or a haptic display would feel the 100 Hz liver as a buzz. Liver steps around a
// puncture or where the push starts or stops, where the force changes by nature, are left out.
TEST(OperatingLoopNeedle, TheForceAtTheLoopRateIsContinuousAcrossLiverSteps) {
  const ScriptedRun r = run({});
  int compared = 0, within = 0;
  double worst_ratio = 0.0, worst_jump_n = 0.0, largest_force_n = 0.0;
  const auto tick_change_n = [&](std::size_t j, Point3 NeedleShapeOutputs::*force) {
    return change_n(r.ticks[j].needle_shape.*force, r.ticks[j - 1].needle_shape.*force);
  };
  for (std::size_t k = first_needle_tick(r) + kTissueEvery; k + kTissueEvery < r.ticks.size(); ++k) {
    const OperatingLoopOutputs& o = r.ticks[k];
    largest_force_n = std::max(largest_force_n, change_n(o.needle_shape.tip_force_n, {}));
    if (o.time_ns != o.tissue_time_ns) continue;  // not a liver step
    if (r.ticks[k + kTissueEvery].needle_shape.punctures != r.ticks[k - kTissueEvery].needle_shape.punctures) continue;
    const TimeNs period_ns = kTissueEvery * kTick;
    if (after_a_kink(o.time_ns) || after_a_kink(o.time_ns - period_ns) || after_a_kink(o.time_ns + period_ns)) continue;
    for (const auto force : {&NeedleShapeOutputs::tip_force_n, &NeedleShapeOutputs::base_force_n}) {
      const double jump_n = tick_change_n(k, force);
      double between_n = 0.0;
      for (std::size_t j = k - kTissueEvery + 1; j < k + kTissueEvery; ++j)
        if (j != k) between_n = std::max(between_n, tick_change_n(j, force));
      ++compared;
      within += jump_n <= 1.05 * between_n + 1e-9 ? 1 : 0;  // 5 %: the tick-to-tick changes vary as much
      worst_jump_n = std::max(worst_jump_n, jump_n);
      if (between_n > 0.0) worst_ratio = std::max(worst_ratio, jump_n / between_n);
    }
  }
  std::printf(
      "%d liver steps (tip and holder): %d jump no more than the force changes from tick to tick between "
      "liver steps (5 %% margin); worst jump %.2e N, %.3f times that change at most; largest tip force %.3f N\n",
      compared / 2, within, worst_jump_n, worst_ratio, largest_force_n);
  EXPECT_GT(compared, 2 * 50);
  EXPECT_GT(largest_force_n, 0.1);
  EXPECT_EQ(within, compared);
}

/// Every published value of every tick, as doubles (flags as their bit patterns).
std::vector<double> flatten(const ScriptedRun& r) {
  std::vector<double> v;
  for (const OperatingLoopOutputs& o : r.ticks) {
    for (const Point3* p : {&o.tumour_now_m, &o.tumour_ahead_m, &o.needle_tip_m, &o.needle_tip_ahead_m, &o.diaphragm_m,
                            &o.needle_shape.tip_force_n, &o.needle_shape.base_force_n})
      v.insert(v.end(), p->begin(), p->end());
    for (const Point3& p : o.needle_shape.centreline_m) v.insert(v.end(), p.begin(), p.end());
    v.insert(v.end(), o.tumour_now_covariance_m2.begin(), o.tumour_now_covariance_m2.end());
    v.insert(v.end(), {o.tip_to_tumour_m, o.tip_to_tumour_ahead_m, o.needle_shape.tip_depth_m,
                       static_cast<double>(o.needle_shape.punctures), static_cast<double>(o.needle_shape.flags.bits()),
                       static_cast<double>(o.needle.flags.bits()), static_cast<double>(o.tissue.bits()),
                       o.degraded ? 1.0 : 0.0});
    v.insert(v.end(), o.liver_q.begin(), o.liver_q.end());
  }
  return v;
}

TEST(OperatingLoopNeedle, PushAndTickNeverAllocateAndRepeatBitwiseWithAMovedModel) {
  const ScriptedRun first = run({});
  // A copy of the model, moved twice: the coupled needle must not point into a moved object.
  OperatingLoopModel copy = setup().with_needle;
  OperatingLoopModel moved = std::move(copy);
  const OperatingLoopModel again = std::move(moved);
  const ScriptedRun second = run({}, &again);
  EXPECT_EQ(first.allocations, 0u);
  EXPECT_EQ(second.allocations, 0u);
  const std::vector<double> a = flatten(first), b = flatten(second);
  ASSERT_EQ(a.size(), b.size());
  EXPECT_EQ(testing::bits_hash({a}), testing::bits_hash({b}));
}

/// Every needle output of every tick is finite.
void expect_finite(const ScriptedRun& r) {
  for (const OperatingLoopOutputs& o : r.ticks) {
    ASSERT_TRUE(finite(o.needle_tip_m) && finite(o.needle_tip_ahead_m) && finite(o.tumour_now_m) &&
                std::isfinite(o.tip_to_tumour_m));
    ASSERT_TRUE(finite(o.needle_shape.tip_force_n) && finite(o.needle_shape.base_force_n) &&
                std::isfinite(o.needle_shape.tip_depth_m));
    for (const Point3& p : o.needle_shape.centreline_m) ASSERT_TRUE(finite(p));
    for (double q : o.liver_q) ASSERT_TRUE(std::isfinite(q));
  }
}

TEST(OperatingLoopNeedle, LostNeedlePosesHoldTheBaseAndRecover) {
  // The tracker loses the needle at 0.45 s, touching the capsule, for 0.75 s while the hand
  // pushes on: the base is held, flagged; on return the base is 9 mm off, more than the
  // needle's 5 mm one-step limit: it glides there (flagged), then follows again.
  Script script;
  script.duration_ns = 1600 * kNsPerMs;
  script.gap_from = 450 * kNsPerMs;
  script.gap_to = 1200 * kNsPerMs;
  const ScriptedRun r = run(script);
  expect_finite(r);
  const OperatingLoopOutputs& held_early = r.ticks[at(600 * kNsPerMs)];
  const OperatingLoopOutputs& held_late = r.ticks[at(1150 * kNsPerMs)];
  EXPECT_TRUE(held_early.needle.degraded && held_early.degraded);
  EXPECT_TRUE(held_late.needle.flags.has(HealthFlag::missing_input));
  EXPECT_EQ(held_early.needle_shape.base_pose.position_m, held_late.needle_shape.base_pose.position_m);
  EXPECT_GT(base_error_m(held_late, 1150 * kNsPerMs), 0.005);
  int gliding = 0;
  for (TimeNs t = 1200 * kNsPerMs; t < 1300 * kNsPerMs; t += kTick)
    gliding += r.ticks[at(t)].needle_shape.flags.has(HealthFlag::pose_jump_rejected);
  const OperatingLoopOutputs& back = r.ticks[at(1400 * kNsPerMs)];
  std::printf("ticks gliding back to the re-acquired pose: %d; punctures %d\n", gliding, back.needle_shape.punctures);
  EXPECT_GE(gliding, 1);
  EXPECT_LE(gliding, 5);
  EXPECT_FALSE(back.needle.degraded) << back.needle.flags.bits();
  EXPECT_FALSE(back.needle_shape.flags.has(HealthFlag::pose_jump_rejected));
  EXPECT_FALSE(back.needle_shape.flags.has(HealthFlag::bad_sample));
  EXPECT_LT(base_error_m(back, 1400 * kNsPerMs), 1e-9);
  EXPECT_EQ(back.needle_shape.punctures, 1);
}

TEST(OperatingLoopNeedle, NanNeedlePoseIsRejectedTheBaseHeldAndRecovered) {
  Script script;
  script.nan_at = 600 * kNsPerMs;  // delivered 2 ms later
  const ScriptedRun r = run(script);
  expect_finite(r);
  const OperatingLoopOutputs& hit = r.ticks[at(602 * kNsPerMs)];
  const OperatingLoopOutputs& before = r.ticks[at(601 * kNsPerMs)];
  EXPECT_TRUE(hit.needle.flags.has(HealthFlag::bad_sample));
  EXPECT_TRUE(hit.needle.degraded && hit.degraded);
  EXPECT_EQ(hit.needle_shape.base_pose.position_m, before.needle_shape.base_pose.position_m);  // held
  const OperatingLoopOutputs& recovered = r.ticks[at(700 * kNsPerMs)];
  EXPECT_FALSE(recovered.needle.degraded) << recovered.needle.flags.bits();
  EXPECT_LT(base_error_m(recovered, 700 * kNsPerMs), 1e-9);
}

TEST(OperatingLoopNeedle, BadNeedleDeclarationsAreRefusedByField) {
  const LoopSetup& s = setup();
  const auto field = [&](const OperatingLoopNeedleOptions& needle) {
    auto built = make_operating_loop_model(s.with_needle.rungs[0].reduced, s.with_needle.rungs[0].filter,
                                           s.with_needle.options, needle, s.mesh);
    return built.ok() ? std::string("(built)") : built.error().field;
  };
  OperatingLoopNeedleOptions n = s.needle;
  n.parameters.step_s = 2e-3;
  EXPECT_EQ(field(n), "operating_loop.needle.parameters.step_s");
  n = s.needle;
  n.parameters.element_count = kLoopMaxNeedleNodes;
  EXPECT_EQ(field(n), "operating_loop.needle.parameters.element_count");
  n = s.needle;
  n.parameters.length_m = -1.0;
  EXPECT_EQ(field(n), "operating_loop.needle.parameters.length_m");
  n = s.needle;
  n.marker_from_base.rotation.coeffs() *= 2.0;
  EXPECT_EQ(field(n), "operating_loop.needle.marker_from_base");
  n = s.needle;
  n.max_point_forces = 33;  // the liver's scene takes 32
  EXPECT_EQ(field(n), "operating_loop.needle.max_point_forces");
  n = s.needle;
  n.scene.layers.clear();
  EXPECT_EQ(field(n), "operating_loop.needle.scene.layers");
  const TetMesh other = testing::box_mesh({0.04, 0.02, kTopM}, 0.01);
  auto wrong_mesh = make_operating_loop_model(s.with_needle.rungs[0].reduced, s.with_needle.rungs[0].filter,
                                              s.with_needle.options, s.needle, other);
  ASSERT_FALSE(wrong_mesh.ok());
  EXPECT_EQ(wrong_mesh.error().field, "operating_loop.needle.mesh");
}

}  // namespace
}  // namespace nav
