// The operating loop on an escalation ladder (issue 4, item 3, in the loop): an 8 x 2 x 2 cm
// beam held at x = 0 whose x = 8 cm face is the diaphragm, moved by breathing read from a
// respiratory marker; rung 0 the 3 leading POD directions of quasi-static breaths 2.5 times the
// nominal depth, rung 1 those extended (extend_basis) by 3 directions of breaths 7 times as
// deep, each with corotational cubature trained on its breaths; the loop steps at 50 Hz on a
// 1 kHz tick. A breath 5 times the nominal depth leaves rung 0's envelope: the loop escalates,
// carrying the liver, the filter and the look-ahead to rung 1, and steps back down once the
// breathing is nominal again. Checked against the full-order corotational model of the same
// material under the same breathing (the truth of this test): the tumour estimate is
// continuous at both switches and closer to the truth while escalated than on rung 0 alone;
// with escalation off the ladder loop only flags and equals the one-rung loop bitwise; the
// filter is carried exactly between nested rungs; no allocation, bitwise repeatable; init errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <numbers>
#include <vector>

#include "loop/loop_beam_support.hpp"
#include "nav/core/clock.hpp"
#include "nav/loop/operating_loop.hpp"
#include "nav/reduced/reduced_ladder_basis.hpp"
#include "nav/reduced/reduction.hpp"
#include "nav/tissue/tet_fem_model.hpp"
#include "needle/needle_coupling_support.hpp"
#include "support/allocation_guard.hpp"
#include "tissue/tissue_test_support.hpp"

namespace nav {
namespace {

constexpr int kTissueEvery = 20;  // 50 Hz liver steps on the 1 kHz tick
constexpr double kStepS = 0.02;
constexpr TimeNs kTick = kNsPerMs, kStep = 20 * kNsPerMs;
constexpr TimeNs kDuration = 8 * kNsPerSecond;
constexpr TimeNs kDeepFrom = 2 * kNsPerSecond, kDeepTo = 4 * kNsPerSecond;  // the deep breaths
constexpr double kDeepBreath = 5.0;
constexpr int kSmallR = 3, kBigR = 6;
using testing::diaphragm_at;
using testing::kDiaphragmPerMarker;
using testing::kMarkerMeanM;
using testing::marker_m;

/// The breath's depth at time t (nominal 1, deep between kDeepFrom and kDeepTo).
double depth_at(TimeNs t) { return t >= kDeepFrom && t < kDeepTo ? kDeepBreath : 1.0; }

const TissueSolverOptions kSolver{.integrator = Integrator::quasi_static, .step_s = kStepS, .cg_iterations = 3};

/// Quasi-static full-order breathing of depth depth(t): `node`'s position at every step, and
/// every snapshot_every-th step's displacements into `snapshots`.
template <class Depth>
std::vector<Point3> breathe(const TetMesh& mesh, const TissueScene& scene, Depth depth, int steps, std::int32_t node,
                            std::vector<double>* snapshots, int snapshot_every) {
  const TetFemModel full = make_tet_fem_model(mesh, scene, kSolver).value();
  return testing::breathe(
      full, kStep, depth, [](int) { return 1.0; }, steps, node, snapshots, snapshot_every);
}

ReductionOptions reduction(int r) {
  return {.source = ReducedBasisSource::pod,
          .force_kind = ReducedForceKind::corotational_cubature,
          .basis_size = r,
          .max_cubature_samples = 48};
}

/// The beam, its two nested rungs and their filters, the loop's options and the truth of the
/// tumour (the node at the beam's centre) at every liver step.
struct LadderSetup {
  TetMesh mesh = testing::box_mesh({0.08, 0.02, 0.02}, 0.01);
  TissueScene scene;
  std::int32_t tumour = 0;
  ReducedBasis small, big;
  ReducedSolverOptions solver{
      .integrator = ReducedIntegrator::quasi_static, .step_s = kStepS, .newton_iterations = 2, .frozen_tangent = false};
  ReducedLadderModel ladder{nullptr};  ///< escalation allowed, stepping down after 25 fitting steps
  std::vector<ReducedKalmanModel> filters;
  OperatingLoopOptions options;
  std::vector<Point3> truth;

  LadderSetup() {
    scene.default_material = {10.0e3, 0.3, 1000.0};
    scene.fixed_nodes = testing::nodes_where(mesh, 0, 0.0);
    scene.prescribed_nodes = testing::nodes_where(mesh, 0, 0.08);
    scene.max_point_forces = 32;
    tumour = testing::nearest_node(mesh, {0.04, 0.01, 0.01});
    std::vector<double> nominal, deep;  // one breath each, every 5th step
    breathe(
        mesh, scene, [](TimeNs) { return 2.5; }, 100, tumour, &nominal, 5);
    breathe(
        mesh, scene, [](TimeNs) { return 7.0; }, 100, tumour, &deep, 5);
    small = make_pod_basis(mesh, scene, kSolver, reduction(kSmallR), nominal, 20).value();
    train(small, nominal);
    big = extend_basis(mesh, scene, kSolver, small, kBigR, deep, 20).value();
    train(big, deep);
    ladder = ladder_with(true);
    for (int rung = 0; rung < 2; ++rung) {
      const ReducedBasis& basis = rung == 0 ? small : big;
      ReducedKalmanOptions filter_options;
      filter_options.correction_std = correction_std_from_training(basis, 1.0);
      filter_options.correlation_time_s = 2.0;
      filter_options.observation_std_m = 0.001;
      const ObservedPoint points[] = {observed_node(tumour)};
      filters.push_back(
          make_reduced_kalman_model(mesh, basis, ladder.reduced_rung(rung), points, filter_options).value());
    }
    options.tick_period_ns = kTick;
    options.tissue_every_ticks = kTissueEvery;
    options.display_latency_ns = 100 * kNsPerMs;
    options.diaphragm_per_marker = kDiaphragmPerMarker;
    options.respiratory_reference_m = kMarkerMeanM;
    options.breathing.history_capacity = 900;  // 8 s of marker samples at 100 Hz, and some
    truth = breathe(mesh, scene, depth_at, static_cast<int>(kDuration / kStep) + 2, tumour, nullptr, 1);
  }

  void train(ReducedBasis& basis, const std::vector<double>& snapshots) const {
    const Status trained = add_force_reduction(mesh, scene, kSolver, reduction(basis.basis_size), snapshots, 20, basis);
    EXPECT_TRUE(trained.ok()) << trained.error().describe();
  }

  ReducedLadderModel ladder_with(bool allowed) const {
    ReducedLadderOptions escalation;
    escalation.escalation_allowed = allowed;
    escalation.de_escalate_after_steps = 25;
    const ReducedRungSpec rungs[] = {{small, solver}, {big, solver}};
    return make_reduced_ladder_model(mesh, scene, kSolver, rungs, false, escalation).value();
  }

  OperatingLoopModel loop(const ReducedLadderModel& on) const {
    auto built = make_operating_loop_model(on, filters, options);
    EXPECT_TRUE(built.ok()) << built.error().describe();
    return std::move(built).value();
  }
};

const LadderSetup& setup() {
  static const LadderSetup s;
  return s;
}

/// A run's outputs at every tick, and the allocations of the loop's calls.
struct LoopRun {
  std::vector<OperatingLoopOutputs> ticks;
  std::size_t allocations = 0;
};

/// The breathing marker read every 10 ms without delay (at every liver step the loop's
/// diaphragm is then the truth's, and the tumour error is the model's) and, when `observe`, the true tumour seen at 20
/// Hz (30 ms to segment, noise-free), the loop ticked at 1 kHz.
LoopRun run(const OperatingLoopModel& model, bool observe) {
  const LadderSetup& s = setup();
  OperatingLoopData data = make_operating_loop_data(model).value();
  LoopRun out;
  out.ticks.reserve(static_cast<std::size_t>(kDuration / kTick) + 1);
  TimeNs next_observation = 0;
  testing::AllocationGuard guard;
  for (TimeNs now = 0; now <= kDuration; now += kTick) {
    if (now % (10 * kNsPerMs) == 0)
      push_respiratory_sample(model, data, now, {0.02, -0.01, marker_m(now, depth_at(now))});
    for (; next_observation + 30 * kNsPerMs <= now; next_observation += 50 * kNsPerMs)
      if (observe)
        push_tumour_observation(data, next_observation, s.truth[static_cast<std::size_t>(next_observation / kStep)]);
    tick(model, data, now);
    out.ticks.push_back(data.outputs);
  }
  out.allocations = guard.allocations();
  return out;
}

double error_m(const Point3& a, const Point3& b) { return std::hypot(a[0] - b[0], a[1] - b[1], a[2] - b[2]); }
std::size_t at(TimeNs t) { return static_cast<std::size_t>(t / kTick); }

/// RMS of |tumour now - truth| over the liver steps in [from, to).
double rms_error_m(const LoopRun& r, TimeNs from, TimeNs to) {
  double sum = 0.0;
  int n = 0;
  for (TimeNs t = from; t < to; t += kStep, ++n) {
    const double e = error_m(r.ticks[at(t)].tumour_now_m, setup().truth[static_cast<std::size_t>(t / kStep)]);
    sum += e * e;
  }
  return std::sqrt(sum / n);
}

/// The largest change of the tumour estimate, and of the truth, from one liver step to the next
/// around liver tick `tick` (two steps either side).
std::pair<double, double> largest_changes_m(const LoopRun& r, std::size_t tick) {
  double estimate = 0.0, truth = 0.0;
  for (std::size_t k = tick - 2 * kTissueEvery; k <= tick + 2 * kTissueEvery; k += kTissueEvery) {
    estimate = std::max(estimate, error_m(r.ticks[k].tumour_now_m, r.ticks[k - kTissueEvery].tumour_now_m));
    truth = std::max(truth, error_m(setup().truth[k / kTissueEvery], setup().truth[k / kTissueEvery - 1]));
  }
  return {estimate, truth};
}

TEST(OperatingLoopLadder, EscalatesOnDeepBreathsAndStepsBackDown) {
  const LadderSetup& s = setup();
  ASSERT_LT(s.ladder.transfer_loss(0), 1e-9);  // nested rungs: the transfer is exact
  const LoopRun ladder = run(s.loop(s.ladder), false);
  const LoopRun flat = run(s.loop(s.ladder_with(false)), false);
  std::size_t up = 0, down = 0;
  for (std::size_t k = 1; k < ladder.ticks.size(); ++k) {
    const OperatingLoopOutputs& o = ladder.ticks[k];
    if (o.liver_rung > ladder.ticks[k - 1].liver_rung) up = k;
    if (o.liver_rung < ladder.ticks[k - 1].liver_rung) down = k;
    ASSERT_TRUE(std::isfinite(o.tumour_now_m[0]) && std::isfinite(o.tumour_ahead_m[2])) << "tick " << k;
  }
  const OperatingLoopOutputs& last = ladder.ticks.back();
  EXPECT_EQ(last.escalations, 1);
  EXPECT_EQ(last.de_escalations, 1);
  EXPECT_EQ(last.liver_rung, 0);
  ASSERT_GT(up, at(kDeepFrom));
  ASSERT_LT(up, at(kDeepTo));
  ASSERT_GT(down, at(kDeepTo));
  EXPECT_TRUE(ladder.ticks[up].tissue.has(HealthFlag::reduced_escalated));
  for (std::size_t k = 0; k < at(kDeepFrom); ++k) ASSERT_EQ(ladder.ticks[k].liver_rung, 0) << "tick " << k;
  // Continuity: at each switch the estimate moves no more than the truth moves about it,
  // plus the model error the switch corrects (bounded by rung 0's error there).
  const auto [up_change_m, up_truth_m] = largest_changes_m(ladder, up);
  const auto [down_change_m, down_truth_m] = largest_changes_m(ladder, down);
  const double rung0_error_m = error_m(flat.ticks[up].tumour_now_m, s.truth[up / kTissueEvery]);
  // Accuracy while escalated, against staying on rung 0 (open loop: no observation).
  const double escalated_m = rms_error_m(ladder, static_cast<TimeNs>(up) * kTick, static_cast<TimeNs>(down) * kTick);
  const double stayed_m = rms_error_m(flat, static_cast<TimeNs>(up) * kTick, static_cast<TimeNs>(down) * kTick);
  std::printf(
      "escalated at %.2f s, stepped down at %.2f s; tumour error while escalated %.4f mm RMS (rung 0 alone %.4f mm); "
      "largest step change at the switch up %.4f mm (truth %.4f mm, rung 0 error %.4f mm), down %.4f mm (truth %.4f "
      "mm)\n",
      1e-3 * static_cast<double>(up), 1e-3 * static_cast<double>(down), 1e3 * escalated_m, 1e3 * stayed_m,
      1e3 * up_change_m, 1e3 * up_truth_m, 1e3 * rung0_error_m, 1e3 * down_change_m, 1e3 * down_truth_m);
  EXPECT_LT(escalated_m, 0.25 * stayed_m);
  EXPECT_LE(up_change_m, 1.05 * up_truth_m + rung0_error_m);
  EXPECT_LE(down_change_m, 1.05 * down_truth_m + 0.02 * 1e-3);
}

TEST(OperatingLoopLadder, WithEscalationOffItFlagsAndEqualsTheOneRungLoopBitwise) {
  const LadderSetup& s = setup();
  const LoopRun off = run(s.loop(s.ladder_with(false)), true);
  const OperatingLoopModel one = make_operating_loop_model(s.ladder.reduced_rung(0), s.filters[0], s.options).value();
  const LoopRun plain = run(one, true);
  ASSERT_EQ(off.ticks.size(), plain.ticks.size());
  int flagged = 0, mismatches = 0;
  for (std::size_t k = 0; k < off.ticks.size(); ++k) {
    const OperatingLoopOutputs& a = off.ticks[k];
    const OperatingLoopOutputs& b = plain.ticks[k];
    flagged += a.tissue.has(HealthFlag::reduced_out_of_envelope) && a.tissue_time_ns == a.time_ns;
    mismatches += a.liver_rung != 0 || std::memcmp(&a.tumour_now_m, &b.tumour_now_m, sizeof(Point3)) != 0 ||
                  std::memcmp(&a.tumour_ahead_m, &b.tumour_ahead_m, sizeof(Point3)) != 0 ||
                  std::memcmp(a.liver_q.data(), b.liver_q.data(), sizeof(double) * kLoopMaxBasisSize) != 0 ||
                  a.tissue.bits() != b.tissue.bits();
  }
  std::printf("escalation off: %d liver steps flagged out of rung 0's envelope\n", flagged);
  EXPECT_GT(flagged, 10);
  EXPECT_EQ(mismatches, 0);
}

TEST(OperatingLoopLadder, CarriesTheFilterExactlyBetweenNestedRungs) {
  // Nested rungs: T = [I; 0], so the correction and its covariance go up as [dq; 0] and
  // blockdiag(P, S_new), and come back down unchanged.
  const LadderSetup& s = setup();
  const OperatingLoopModel model = s.loop(s.ladder);
  OperatingLoopData data = make_operating_loop_data(model).value();
  ReducedKalmanData& small = data.rungs[0].filter;
  ReducedKalmanData& big = data.rungs[1].filter;
  const int n = kSmallR, m = kBigR;
  for (int i = 0; i < n; ++i) {
    small.correction[static_cast<std::size_t>(i)] = 0.1 * (i + 1);
    for (int j = 0; j < n; ++j)
      small.covariance[static_cast<std::size_t>(i * n + j)] = (i == j ? 2.0 : 0.0) + 0.1 / (1 + i + j);
  }
  small.accepted_updates = 7;
  const OperatingLoopRung& upper = model.rungs[1];
  carry_filter(model.rungs[0].filter, small, upper.filter, big, upper.up_from_below, upper.unseen_prior,
               data.transfer_workspace);
  double worst = 0.0;
  for (int i = 0; i < m; ++i) {
    const double dq = i < n ? small.correction[static_cast<std::size_t>(i)] : 0.0;
    worst = std::max(worst, std::abs(big.correction[static_cast<std::size_t>(i)] - dq));
    for (int j = 0; j < m; ++j) {
      double expected = 0.0;
      if (i < n && j < n) expected = small.covariance[static_cast<std::size_t>(i * n + j)];
      if (i >= n && i == j) expected = upper.filter.prior_variance[static_cast<std::size_t>(i)];
      worst = std::max(
          worst, std::abs(big.covariance[static_cast<std::size_t>(i * m + j)] - expected) / (1.0 + std::abs(expected)));
    }
  }
  EXPECT_LT(worst, 1e-9);
  EXPECT_EQ(big.accepted_updates, 7);
  ReducedKalmanData& back = data.rungs[0].filter;
  std::vector<double> before(small.covariance.begin(), small.covariance.end());
  carry_filter(upper.filter, big, model.rungs[0].filter, back, upper.down_to_below, {}, data.transfer_workspace);
  double round_trip = 0.0;
  for (std::size_t k = 0; k < before.size(); ++k)
    round_trip = std::max(round_trip, std::abs(back.covariance[k] - before[k]));
  EXPECT_LT(round_trip, 1e-9);
}

TEST(OperatingLoopLadder, NeverAllocatesAndRepeatsBitwise) {
  const LadderSetup& s = setup();
  const OperatingLoopModel model = s.loop(s.ladder);
  const LoopRun a = run(model, true), b = run(model, true);
  EXPECT_EQ(a.allocations, 0u);
  EXPECT_EQ(a.ticks.back().escalations, 1);
  ASSERT_EQ(a.ticks.size(), b.ticks.size());
  int mismatches = 0;
  for (std::size_t k = 0; k < a.ticks.size(); ++k)
    mismatches +=
        std::memcmp(&a.ticks[k].tumour_now_m, &b.ticks[k].tumour_now_m, sizeof(Point3)) != 0 ||
        std::memcmp(a.ticks[k].liver_q.data(), b.ticks[k].liver_q.data(), sizeof(double) * kLoopMaxBasisSize) != 0 ||
        a.ticks[k].liver_rung != b.ticks[k].liver_rung;
  EXPECT_EQ(mismatches, 0);
}

/// A run with a needle pushed at 20 mm/s into the top face over the tumour from 0.1 s, its
/// marker pose measured every 4 ms (no delay), the breathing nominal.
LoopRun run_with_needle(const OperatingLoopModel& model, const RigidPose& marker_from_base, TimeNs duration_ns) {
  OperatingLoopData data = make_operating_loop_data(model).value();
  LoopRun out;
  out.ticks.reserve(static_cast<std::size_t>(duration_ns / kTick) + 1);
  const RigidPose base_from_marker = inverse(marker_from_base);
  testing::AllocationGuard guard;
  for (TimeNs now = 0; now <= duration_ns; now += kTick) {
    if (now % (10 * kNsPerMs) == 0) push_respiratory_sample(model, data, now, {0.02, -0.01, marker_m(now, 1.0)});
    if (now % (4 * kNsPerMs) == 0) {
      const double lowered_m = std::clamp(0.02 * 1e-9 * static_cast<double>(now - 100 * kNsPerMs), 0.0, 0.016);
      const NeedlePose p = testing::needle_above(0.04, 0.01, 0.02, lowered_m);
      const RigidPose base{
          {p.position_m[0], p.position_m[1], p.position_m[2]},
          Eigen::Quaterniond(p.rotation_wxyz[0], p.rotation_wxyz[1], p.rotation_wxyz[2], p.rotation_wxyz[3])};
      push_needle_pose(model, data, {now, compose(base, base_from_marker)});
    }
    tick(model, data, now);
    out.ticks.push_back(data.outputs);
  }
  out.allocations = guard.allocations();
  return out;
}

double distance_m(const Point3& a, const Point3& b) { return error_m(a, b); }

TEST(OperatingLoopLadder, ANeedlePushEscalatesAndTheNeedleIsCarriedAlong) {
  // The rungs were trained on breathing alone: the needle's forces take rung 0 out of its
  // envelope and the loop escalates mid-push, the needle (beam, layer, path, forces) carried
  // to rung 1's coupling. Until then the ladder loop is the one-rung loop, bitwise.
  const LadderSetup& s = setup();
  OperatingLoopNeedleOptions needle;
  needle.scene = testing::top_face_layer(0.04, 0.01, 0.02, 0.003);
  needle.marker_from_base = {{0.0, 0.0, -0.01},
                             Eigen::Quaterniond(Eigen::AngleAxisd(0.5 * std::numbers::pi, Eigen::Vector3d::UnitY()))};
  const OperatingLoopModel ladder = make_operating_loop_model(s.ladder, s.filters, s.options, &needle, &s.mesh).value();
  const OperatingLoopModel one =
      make_operating_loop_model(s.ladder.reduced_rung(0), s.filters[0], s.options, needle, s.mesh).value();
  const TimeNs duration = 900 * kNsPerMs;
  const LoopRun a = run_with_needle(ladder, needle.marker_from_base, duration);
  const LoopRun b = run_with_needle(one, needle.marker_from_base, duration);
  EXPECT_EQ(a.allocations, 0u);
  std::size_t up = 0;
  for (std::size_t k = 1; k < a.ticks.size() && up == 0; ++k)
    if (a.ticks[k].liver_rung > a.ticks[k - 1].liver_rung) up = k;
  ASSERT_GT(up, 0u) << "never escalated";
  int mismatches = 0;
  for (std::size_t k = 0; k < up; ++k)
    mismatches += std::memcmp(&a.ticks[k].needle_tip_m, &b.ticks[k].needle_tip_m, sizeof(Point3)) != 0 ||
                  std::memcmp(&a.ticks[k].tumour_now_m, &b.ticks[k].tumour_now_m, sizeof(Point3)) != 0;
  EXPECT_EQ(mismatches, 0);
  ASSERT_GT(a.ticks[up].needle_shape.tip_depth_m + a.ticks[up].needle_shape.tip_force_n[2], 0.0)
      << "escalated before contact";
  // The tip and its force across the switch against their largest tick-to-tick change before it.
  double tip_before_m = 0.0, force_before_n = 0.0;
  for (std::size_t k = up - 40; k < up; ++k) {
    tip_before_m = std::max(tip_before_m, distance_m(a.ticks[k].needle_tip_m, a.ticks[k - 1].needle_tip_m));
    force_before_n = std::max(force_before_n,
                              distance_m(a.ticks[k].needle_shape.tip_force_n, a.ticks[k - 1].needle_shape.tip_force_n));
  }
  const double tip_switch_m = distance_m(a.ticks[up].needle_tip_m, a.ticks[up - 1].needle_tip_m);
  const double force_switch_n =
      distance_m(a.ticks[up].needle_shape.tip_force_n, a.ticks[up - 1].needle_shape.tip_force_n);
  const OperatingLoopOutputs& last = a.ticks.back();
  std::printf(
      "needle push: escalated at %.3f s (tip depth %.2f mm); tip moved %.4f mm over the switch (largest before %.4f "
      "mm), "
      "tip force changed %.4f N (largest before %.4f N); at the end rung %d, %d puncture(s), tip force %.3f N "
      "(one-rung loop: %d, %.3f N)\n",
      1e-3 * static_cast<double>(up), 1e3 * a.ticks[up].needle_shape.tip_depth_m, 1e3 * tip_switch_m,
      1e3 * tip_before_m, force_switch_n, force_before_n, last.liver_rung, last.needle_shape.punctures,
      last.needle_shape.tip_force_n[2], b.ticks.back().needle_shape.punctures,
      b.ticks.back().needle_shape.tip_force_n[2]);
  EXPECT_LE(tip_switch_m, 2.0 * tip_before_m);
  EXPECT_LE(force_switch_n, 2.0 * force_before_n + 0.01);
  EXPECT_EQ(last.needle_shape.punctures, 1);
  EXPECT_TRUE(last.needle_shape.node_count > 0 && std::isfinite(last.needle_tip_m[2]));
}

TEST(OperatingLoopLadder, BuildErrorsNameTheirField) {
  const LadderSetup& s = setup();
  std::vector<ReducedKalmanModel> one{s.filters[0]};
  EXPECT_EQ(make_operating_loop_model(s.ladder, one, s.options).error().field, "operating_loop.filters");
  std::vector<ReducedKalmanModel> swapped{s.filters[1], s.filters[0]};
  EXPECT_EQ(make_operating_loop_model(s.ladder, swapped, s.options).error().field, "operating_loop.filters[0]");
  const ReducedRungSpec rungs[] = {{s.small, s.solver}, {s.big, s.solver}};
  const ReducedLadderModel topped = make_reduced_ladder_model(s.mesh, s.scene, kSolver, rungs, true, {}).value();
  EXPECT_EQ(make_operating_loop_model(topped, s.filters, s.options).error().field, "operating_loop.ladder");
}

}  // namespace
}  // namespace nav
