// The escalation ladder of the reduced liver (issue 4, items 3 and 7), on an 8 cm beam held at
// one end (1536 tetrahedra, corotational, no gravity, a tip force). Rung 0: the r = 2 leading
// POD directions of a quasi-static tip-force ramp up to the full load, with corotational
// cubature trained on it; rung 1: the same 2 directions extended (extend_basis) by 4 POD
// directions of a ramp up to 6 times the load, trained on it; optionally the full-order
// TetFemModel on top. Checked: the transfer operators carry a state of the small basis exactly
// (1e-12) to the big rung and to the full order and back; a load ramped to 5x the training
// load makes rung 0 flag and the ladder escalate, the field continuous at the switch and the
// result closer to the full-order reference; with escalation off the ladder only flags and
// stays bitwise on its rung; the count of flagged steps before escalating; stepping down once
// the load is released; zero allocation across escalations up to the full order; bitwise
// repeatability; no NaN at r = 1 with 0.1 ms and 100 ms steps; init errors.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "nav/reduced/reduced_ladder.hpp"
#include "nav/reduced/reduced_ladder_basis.hpp"
#include "nav/reduced/reduction.hpp"
#include "reduced/reduced_test_support.hpp"
#include "support/allocation_guard.hpp"

namespace nav {
namespace {

using testing::BeamScene;
using testing::bits_hash;
using testing::nodes_where;

/// The beam, its full-order settings, training snapshots (quasi-static tip-force ramps to the
/// full load and to 6 times it) and the POD of the first.
struct TrainedLadder {
  BeamScene beam{{0.08, 0.02, 0.02}, 0.005};
  TissueSolverOptions training_solver;  ///< quasi-static, for the training snapshots
  PointForce tip{};
  std::vector<double> snapshots, wide_snapshots;
  ReducedBasis pod;
  ReducedBasis small2, big2;  ///< small(2) and big(2), built once
  static constexpr int kSnapshots = 8, kWideSnapshots = 16, kExtra = 4;

  TrainedLadder() {
    beam.scene.gravity_m_s2 = {0.0, 0.0, 0.0};  // the tip force alone: about 6 mm of sag at full load
    training_solver.integrator = Integrator::quasi_static;
    training_solver.cg_iterations = 3;
    tip = {static_cast<std::int32_t>(beam.mesh.nodes_m.size() - 1), {0.0, 0.001, -0.002}};
    const TetFemModel full = make_tet_fem_model(beam.mesh, beam.scene, training_solver).value();
    snapshots = testing::ramp_snapshots(full, tip, kSnapshots, 1.0 / (2 * kSnapshots));
    wide_snapshots = testing::ramp_snapshots(full, tip, kWideSnapshots, 6.0 / (2 * kWideSnapshots));
    pod = make_pod_basis(beam.mesh, beam.scene, training_solver, reduction(2), snapshots, kSnapshots).value();
    small2 = small(2);
    big2 = big(2);
  }

  static ReductionOptions reduction(int r) {
    ReductionOptions options;
    options.source = ReducedBasisSource::pod;
    options.basis_size = r;
    options.max_cubature_samples = 48;
    return options;
  }

  /// Fills the cubature and envelope of `basis` from the full-load training, or the 6x one.
  void train(ReducedBasis& basis, bool wide) const {
    const Status status =
        add_force_reduction(beam.mesh, beam.scene, training_solver, reduction(basis.basis_size),
                            wide ? wide_snapshots : snapshots, wide ? kWideSnapshots : kSnapshots, basis);
    EXPECT_TRUE(status.ok()) << status.error().describe();
  }

  /// The r (1 or 2) leading POD directions of the full-load training, trained on it.
  ReducedBasis small(int r) const {
    ReducedBasis basis = pod;
    basis.basis_size = r;
    basis.basis.resize(3 * beam.mesh.nodes_m.size() * static_cast<std::size_t>(r));
    basis.column_values.resize(static_cast<std::size_t>(r));
    train(basis, false);
    return basis;
  }

  /// small(r) extended by kExtra directions of the 6x training, trained on it.
  ReducedBasis big(int r) const {
    auto basis =
        extend_basis(beam.mesh, beam.scene, training_solver, small(r), r + kExtra, wide_snapshots, kWideSnapshots);
    EXPECT_TRUE(basis.ok()) << basis.error().describe();
    train(basis.value(), true);
    return std::move(basis).value();
  }

  TissueInputs load(double scale) const {
    TissueInputs inputs;
    inputs.load_scale = scale;
    inputs.point_forces = std::span<const PointForce>(&tip, 1);
    return inputs;
  }
};

/// Matching settings of the full order and of the reduced rungs.
struct Settings {
  TissueSolverOptions full;
  ReducedSolverOptions reduced;
};

/// Corotational implicit Euler with mass damping.
Settings dynamic(double step_s) {
  Settings s;
  s.full.integrator = Integrator::implicit_euler;
  s.full.cg_iterations = 3;
  s.full.step_s = step_s;
  s.full.rayleigh_mass_per_s = 20.0;
  s.reduced.step_s = step_s;
  s.reduced.newton_iterations = 2;
  s.reduced.rayleigh_mass_per_s = 20.0;
  return s;
}

/// Quasi-static steps towards equilibrium: one Newton step a call on the full order, three
/// with a rebuilt tangent on the reduced rungs.
Settings quasi_static() {
  Settings s;
  s.full.integrator = Integrator::quasi_static;
  s.full.cg_iterations = 3;
  s.reduced.integrator = ReducedIntegrator::quasi_static;
  s.reduced.step_s = s.full.step_s;
  s.reduced.newton_iterations = 3;
  s.reduced.frozen_tangent = false;
  return s;
}

const TrainedLadder& trained_ladder() {
  static const TrainedLadder instance;
  return instance;
}

/// The ladder small(r) -> big(r), optionally topped by the full order.
ReducedLadderModel ladder_of(int r, bool full_order, const ReducedLadderOptions& options,
                             const Settings& settings = dynamic(0.01)) {
  const TrainedLadder& t = trained_ladder();
  const std::vector<ReducedRungSpec> rungs{{r == 2 ? t.small2 : t.small(r), settings.reduced},
                                           {r == 2 ? t.big2 : t.big(r), settings.reduced}};
  auto model = make_reduced_ladder_model(t.beam.mesh, t.beam.scene, settings.full, rungs, full_order, options);
  EXPECT_TRUE(model.ok()) << model.error().describe();
  return std::move(model).value();
}

/// The load of step i: ramped from 0.05 to 5 times the training load over 100 steps, then held.
double ramp(int i) { return std::min(5.0, 0.05 * (i + 1)); }

std::vector<double> all_displacements(const ReducedLadderModel& model, const ReducedLadderData& data) {
  std::vector<double> u(3 * static_cast<std::size_t>(model.node_count()));
  reconstruct_all_displacements_m(model, data, u);
  return u;
}

double max_abs(std::span<const double> v) {
  double m = 0.0;
  for (double value : v) m = std::max(m, std::abs(value));
  return m;
}

double max_difference(std::span<const double> a, std::span<const double> b) {
  double m = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) m = std::max(m, std::abs(a[i] - b[i]));
  return m;
}

/// RMS over nodes of the nodal distance between two displacement fields.
double rms_distance(std::span<const double> a, std::span<const double> b) {
  double sum = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) sum += (a[i] - b[i]) * (a[i] - b[i]);
  return std::sqrt(sum / static_cast<double>(a.size() / 3));
}

/// Full-order displacements after each of `steps` steps of the ramp.
std::vector<std::vector<double>> full_order_reference(int steps, const Settings& settings) {
  const TrainedLadder& t = trained_ladder();
  const TetFemModel full = make_tet_fem_model(t.beam.mesh, t.beam.scene, settings.full).value();
  auto data = make_tet_fem_data(full).value();
  std::vector<std::vector<double>> history;
  for (int i = 0; i < steps; ++i) {
    step(full, data, t.load(ramp(i)));
    std::vector<double> u(data.positions_m.size());
    for (std::size_t k = 0; k < u.size(); ++k) u[k] = data.positions_m[k] - full.rest_positions_m()[k];
    history.push_back(std::move(u));
  }
  return history;
}

TEST(ReducedLadder, TransferCarriesASmallBasisStateExactly) {
  // A scene with a diaphragm region at the free end, so that the lift is carried too.
  const TrainedLadder& t = trained_ladder();
  TissueScene scene = t.beam.scene;
  scene.prescribed_nodes = nodes_where(t.beam.mesh, 0, 0.08);
  ReductionOptions modes;
  modes.source = ReducedBasisSource::linear_modes;
  modes.force_kind = ReducedForceKind::linear;
  modes.basis_size = 10;
  const ReducedBasis big = make_modal_basis(t.beam.mesh, scene, dynamic(0.01).full, modes).value();
  ReducedBasis small = big;
  small.basis_size = 4;
  small.basis.resize(3 * t.beam.mesh.nodes_m.size() * 4);
  small.column_values.resize(4);
  const std::vector<ReducedRungSpec> rungs{{small, dynamic(0.01).reduced}, {big, dynamic(0.01).reduced}};
  const auto model = make_reduced_ladder_model(t.beam.mesh, scene, dynamic(0.01).full, rungs, true, {});
  ASSERT_TRUE(model.ok()) << model.error().describe();
  const ReducedLadderModel& ladder = model.value();
  EXPECT_EQ(ladder.rung_count(), 3);
  EXPECT_LT(std::abs(ladder.transfer_loss(0)), 1e-12);
  auto data = make_reduced_ladder_data(ladder).value();
  const double q[4] = {2e-3, -1e-3, 5e-4, 3e-4}, v[4] = {1e-2, 2e-3, -4e-3, 1e-3}, d[3] = {0.0, 1e-3, -2e-3};
  std::copy(q, q + 4, data.reduced[0].q.begin());
  std::copy(v, v + 4, data.reduced[0].q_velocity.begin());
  std::copy(d, d + 3, data.reduced[0].prescribed_m);
  const std::vector<double> small_u = all_displacements(ladder, data);
  const double scale = max_abs(small_u);
  ASSERT_GT(scale, 1e-3);
  move_to_rung(ladder, data, 1);
  EXPECT_EQ(data.active_rung, 1);
  EXPECT_LT(max_difference(all_displacements(ladder, data), small_u), 1e-12 * scale);
  for (int j = 4; j < 10; ++j) EXPECT_LT(std::abs(data.reduced[1].q[static_cast<std::size_t>(j)]), 1e-14);
  move_to_rung(ladder, data, 2);
  EXPECT_EQ(data.active_rung, 2);
  EXPECT_LT(max_difference(all_displacements(ladder, data), small_u), 1e-12 * scale);
  // Lazy reconstruction from the full order agrees, and a node out of range gives zeros.
  const std::vector<std::int32_t> nodes{7, scene.prescribed_nodes[0], -1};
  std::vector<double> some(9, 1.0);
  reconstruct_displacements_m(ladder, data, nodes, some);
  for (std::size_t k = 0; k < 2; ++k)
    for (std::size_t c = 0; c < 3; ++c)
      EXPECT_EQ(some[3 * k + c], all_displacements(ladder, data)[3 * static_cast<std::size_t>(nodes[k]) + c]);
  EXPECT_NEAR(some[4], d[1], 1e-15);  // the diaphragm node follows d
  EXPECT_EQ(some[6], 0.0);
  // Down again by the M-projection: the coordinates and velocities come back.
  move_to_rung(ladder, data, 0);
  for (std::size_t j = 0; j < 4; ++j) {
    EXPECT_NEAR(data.reduced[0].q[j], q[j], 1e-12 * std::abs(q[0]));
    EXPECT_NEAR(data.reduced[0].q_velocity[j], v[j], 1e-12 * std::abs(v[0]));
  }
}

/// A ladder run on the ramp: its final field, and at each escalation the change of the field
/// over that step, the full order's change over the same step and the ladder's error against
/// the full order before it.
struct LadderRun {
  std::vector<double> final_u;
  std::vector<int> switch_steps;
  std::vector<double> jumps_m, reference_increments_m, errors_before_m;
  HealthFlags health;
  int active_rung = 0;
};

LadderRun run_ramp(const ReducedLadderModel& ladder, const std::vector<std::vector<double>>& reference) {
  auto data = make_reduced_ladder_data(ladder).value();
  LadderRun run;
  std::vector<double> before = all_displacements(ladder, data);
  for (std::size_t i = 0; i < reference.size(); ++i) {
    step(ladder, data, trained_ladder().load(ramp(static_cast<int>(i))));
    const std::vector<double> after = all_displacements(ladder, data);
    if (data.report.escalated && i > 0) {
      EXPECT_GT(data.report.envelope_ratio, 1.5);  // the lower rung's indicator fired
      run.switch_steps.push_back(static_cast<int>(i));
      run.jumps_m.push_back(max_difference(after, before));
      run.reference_increments_m.push_back(max_difference(reference[i], reference[i - 1]));
      run.errors_before_m.push_back(max_difference(before, reference[i - 1]));
    }
    before = after;
  }
  run.final_u = before;
  run.health = data.health;
  run.active_rung = data.active_rung;
  return run;
}

TEST(ReducedLadder, FiveTimesTheTrainingLoadEscalatesContinuouslyAndCloser) {
  // Quasi-static: every rung sits at its own equilibrium of the load, so that the figures
  // compare models, not transients.
  const Settings settings = quasi_static();
  const auto reference = full_order_reference(120, settings);
  ReducedLadderOptions off;
  off.escalation_allowed = false;
  const ReducedLadderModel two_rungs = ladder_of(2, false, {}, settings);
  EXPECT_LT(std::abs(two_rungs.transfer_loss(0)), 1e-12);  // extend_basis nests the rungs
  const LadderRun staying = run_ramp(ladder_of(2, false, off, settings), reference);
  const LadderRun escalated = run_ramp(two_rungs, reference);
  const LadderRun to_full = run_ramp(ladder_of(2, true, {}, settings), reference);
  EXPECT_TRUE(staying.switch_steps.empty());
  EXPECT_TRUE(staying.health.has(HealthFlag::reduced_out_of_envelope));
  ASSERT_EQ(escalated.switch_steps.size(), 1u);
  EXPECT_EQ(escalated.active_rung, 1);
  ASSERT_EQ(to_full.switch_steps.size(), 2u);  // on to the full order
  EXPECT_EQ(to_full.active_rung, 2);
  for (const LadderRun* run : {&escalated, &to_full}) {
    EXPECT_TRUE(run->health.has(HealthFlag::reduced_escalated));
    EXPECT_TRUE(run->health.has(HealthFlag::reduced_out_of_envelope));
    EXPECT_FALSE(run->health.has(HealthFlag::non_finite_state));
    // Continuity: the state is carried exactly, so the switching step moves the field by the
    // load's own increment plus at most the lower rung's error that the higher rung corrects
    // (largest nodal values; 10 % margin). A lost or wrong transfer would throw the field back
    // towards rest, by the whole displacement.
    for (std::size_t k = 0; k < run->switch_steps.size(); ++k) {
      const double bound_m = 1.1 * (run->reference_increments_m[k] + run->errors_before_m[k]);
      std::printf(
          "switch to rung %d at step %d (load %.2fx): field change %.3f mm; full-order change %.3f mm, error before "
          "%.3f mm\n",
          run->active_rung - static_cast<int>(run->switch_steps.size() - 1 - k), run->switch_steps[k],
          ramp(run->switch_steps[k]), 1e3 * run->jumps_m[k], 1e3 * run->reference_increments_m[k],
          1e3 * run->errors_before_m[k]);
      EXPECT_LT(run->jumps_m[k], bound_m);
    }
  }
  // Accuracy at 5x the training load: escalating brings the ladder to the full order.
  const double largest = max_abs(reference.back());
  double rms[3] = {}, worst[3] = {};
  const LadderRun* runs[3] = {&staying, &escalated, &to_full};
  for (int k = 0; k < 3; ++k) {
    rms[k] = rms_distance(runs[k]->final_u, reference.back());
    worst[k] = max_difference(runs[k]->final_u, reference.back());
  }
  std::printf(
      "at 5x (largest displacement %.2f mm), RMS / worst nodal error against the full order: r = 2 stays %.3f / %.3f "
      "mm "
      "(%.2f %%), escalated to r = 6 %.3f / %.3f mm (%.2f %%), escalated to the full order %.2e / %.2e mm\n",
      1e3 * largest, 1e3 * rms[0], 1e3 * worst[0], 100.0 * rms[0] / largest, 1e3 * rms[1], 1e3 * worst[1],
      100.0 * rms[1] / largest, 1e3 * rms[2], 1e3 * worst[2]);
  EXPECT_LT(rms[1], 0.1 * rms[0]);
  EXPECT_LT(worst[1], 0.1 * worst[0]);
  EXPECT_LT(rms[2], 1e-3 * rms[0]);
}

TEST(ReducedLadder, EscalationOffOnlyFlagsAndStaysOnItsRung) {
  ReducedLadderOptions off;
  off.escalation_allowed = false;
  const ReducedLadderModel ladder = ladder_of(2, true, off);
  auto data = make_reduced_ladder_data(ladder).value();
  // The rung alone, as a plain ReducedModel: the ladder must be bitwise the same.
  const TrainedLadder& t = trained_ladder();
  const ReducedModel alone =
      make_reduced_model(t.beam.mesh, t.beam.scene, dynamic(0.01).full, t.small2, dynamic(0.01).reduced).value();
  auto alone_data = make_reduced_data(alone).value();
  for (int i = 0; i < 120; ++i) {
    step(ladder, data, t.load(ramp(i)));
    step(alone, alone_data, t.load(ramp(i)));
  }
  EXPECT_EQ(data.active_rung, 0);
  EXPECT_EQ(data.escalations, 0);
  EXPECT_GT(data.flagged_steps, 10);
  EXPECT_TRUE(data.health.has(HealthFlag::reduced_out_of_envelope));
  EXPECT_FALSE(data.health.has(HealthFlag::reduced_escalated));
  EXPECT_EQ(bits_hash({data.reduced[0].q, data.reduced[0].q_velocity}),
            bits_hash({alone_data.q, alone_data.q_velocity}));
}

TEST(ReducedLadder, FlaggedStepsCountBeforeEscalating) {
  ReducedLadderOptions patient;
  patient.escalate_after_steps = 5;
  const ReducedLadderModel ladder = ladder_of(2, false, patient);
  auto data = make_reduced_ladder_data(ladder).value();
  int first_flag = -1, escalation = -1;
  for (int i = 0; i < 120 && escalation < 0; ++i) {
    step(ladder, data, trained_ladder().load(ramp(i)));
    if (first_flag < 0 && data.health.has(HealthFlag::reduced_out_of_envelope)) first_flag = i;
    if (data.report.escalated) escalation = i;
  }
  ASSERT_GE(first_flag, 0);
  EXPECT_EQ(escalation, first_flag + 4);
}

TEST(ReducedLadder, StepsDownOnceTheLoadIsBackInsideTheSmallEnvelope) {
  ReducedLadderOptions options;
  options.de_escalate_after_steps = 5;
  options.de_escalation_residual = 0.05;
  const ReducedLadderModel ladder = ladder_of(2, false, options);
  auto data = make_reduced_ladder_data(ladder).value();
  for (int i = 0; i < 100; ++i) step(ladder, data, trained_ladder().load(ramp(i)));
  ASSERT_EQ(data.active_rung, 1);
  double residual_at_switch = -1.0, jump_m = 0.0, released_m = 0.0;
  std::vector<double> before = all_displacements(ladder, data);
  for (int i = 0; i < 150 && residual_at_switch < 0.0; ++i) {
    step(ladder, data, trained_ladder().load(0.3));
    const std::vector<double> after = all_displacements(ladder, data);
    if (data.report.de_escalated) {
      residual_at_switch = data.report.projection_residual;
      jump_m = max_difference(after, before);
      released_m = max_abs(after);
    }
    before = after;
  }
  ASSERT_GE(residual_at_switch, 0.0) << "never stepped down";
  EXPECT_EQ(data.active_rung, 0);
  EXPECT_EQ(data.de_escalations, 1);
  std::printf(
      "stepped down at a projection residual of %.2e; the step plus the projection moved the field by %.4f mm of %.2f "
      "mm\n",
      residual_at_switch, 1e3 * jump_m, 1e3 * released_m);
  EXPECT_LE(residual_at_switch, options.de_escalation_residual);
  EXPECT_LT(jump_m,
            2.0 * options.de_escalation_residual * released_m);  // what the small basis drops, largest nodal value
  // Hysteresis: at the released load the small rung stays inside its envelope.
  for (int i = 0; i < 30; ++i) step(ladder, data, trained_ladder().load(0.3));
  EXPECT_EQ(data.active_rung, 0);
  EXPECT_EQ(data.escalations, 1);
}

/// Runs the ramp on a three-rung ladder (r = 2, 6, full order) and returns the hash of the
/// final field; counts the allocations of the steps and the escalations.
std::uint64_t scripted_run(const ReducedLadderModel& ladder, std::size_t& allocations, std::int64_t& escalations) {
  auto data = make_reduced_ladder_data(ladder).value();
  std::vector<double> u(3 * static_cast<std::size_t>(ladder.node_count()));
  {
    testing::AllocationGuard guard;
    for (int i = 0; i < 110; ++i) step(ladder, data, trained_ladder().load(ramp(i)));
    reconstruct_all_displacements_m(ladder, data, u);
    allocations = guard.allocations();
  }
  escalations = data.escalations;
  return bits_hash({u, data.full->velocities_m_s});
}

TEST(ReducedLadder, EscalationsNeverAllocateAndRepeatBitwise) {
  const ReducedLadderModel ladder = ladder_of(2, true, {});
  std::size_t first_allocations = 1, second_allocations = 1;
  std::int64_t escalations = 0;
  const std::uint64_t first = scripted_run(ladder, first_allocations, escalations);
  EXPECT_EQ(escalations, 2);  // up to the full order
  EXPECT_EQ(first_allocations, 0u);
  EXPECT_EQ(scripted_run(ladder, second_allocations, escalations), first);
  EXPECT_EQ(second_allocations, 0u);
}

TEST(ReducedLadder, SingleColumnRungAtExtremeStepsStaysFinite) {
  for (double step_s : {1e-4, 1e-1}) {
    const ReducedLadderModel ladder = ladder_of(1, true, {}, dynamic(step_s));
    auto data = make_reduced_ladder_data(ladder).value();
    for (int i = 0; i < 40; ++i) step(ladder, data, trained_ladder().load(5.0));
    const std::vector<double> u = all_displacements(ladder, data);
    bool finite = true;
    for (double value : u) finite = finite && std::isfinite(value);
    EXPECT_TRUE(finite) << step_s;
    EXPECT_FALSE(data.health.has(HealthFlag::non_finite_state)) << step_s;
    EXPECT_LT(max_abs(u), 0.08) << step_s;  // no blow-up: less than the beam's length
    // 40 steps of 0.1 ms barely move the beam (inside the envelope); 100 ms steps climb the ladder.
    if (step_s > 0.05) {
      EXPECT_TRUE(data.health.has(HealthFlag::reduced_out_of_envelope));
      EXPECT_GE(data.escalations, 1);
    }
    std::printf("r = 1 rung, dt %.4f s: rung %d after %lld escalations, largest displacement %.2f mm\n", step_s,
                data.active_rung, static_cast<long long>(data.escalations), 1e3 * max_abs(u));
  }
}

TEST(ReducedLadder, InitErrorsNameTheField) {
  const TrainedLadder& t = trained_ladder();
  std::vector<ReducedRungSpec> rungs{{t.big2, dynamic(0.01).reduced}, {t.small2, dynamic(0.01).reduced}};
  auto field = [&](bool full, const ReducedLadderOptions& options, const TissueSolverOptions& solver) {
    return make_reduced_ladder_model(t.beam.mesh, t.beam.scene, solver, rungs, full, options).error().field;
  };
  EXPECT_EQ(field(false, {}, dynamic(0.01).full), "rungs[1].basis.basis_size");
  std::swap(rungs[0], rungs[1]);
  rungs[1].options.step_s = 0.02;
  EXPECT_EQ(field(false, {}, dynamic(0.01).full), "rungs[1].options.step_s");
  rungs[1].options.step_s = 0.01;
  EXPECT_EQ(field(true, {}, dynamic(0.02).full), "step_s");
  TissueSolverOptions explicit_solver = dynamic(0.01).full;
  explicit_solver.integrator = Integrator::explicit_central_difference;
  EXPECT_EQ(field(true, {}, explicit_solver), "integrator");
  ReducedLadderOptions options;
  options.escalate_after_steps = 0;
  EXPECT_EQ(field(false, options, dynamic(0.01).full), "escalate_after_steps");
  options = {};
  options.de_escalate_after_steps = 3;
  options.de_escalation_envelope_ratio = 2.0;  // above the envelope factor 1.5
  EXPECT_EQ(field(false, options, dynamic(0.01).full), "de_escalation_envelope_ratio");
  rungs[0].options.newton_iterations = 0;
  EXPECT_EQ(field(false, {}, dynamic(0.01).full), "rungs[0].newton_iterations");
  EXPECT_EQ(make_reduced_ladder_model(t.beam.mesh, t.beam.scene, dynamic(0.01).full, {}, false, {}).error().field,
            "rungs");
}

}  // namespace
}  // namespace nav
