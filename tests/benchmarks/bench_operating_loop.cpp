// Tick cost of the operating loop on the embedded liver (about 5000 tetrahedra, held at its
// attachments, its top 2 cm of boundary nodes a diaphragm region): POD-free vibration modes
// (r = 8 to 64) with corotational cubature (at most 32 sampled tetrahedra, trained on a few
// full-order quasi-static steps under gravity and diaphragm moves), implicit Euler with one
// Newton iteration on the frozen tangent, liver steps every 10th tick of a 1 kHz loop, a 50 ms
// display latency (5 look-ahead steps). After a 3 s warm-up on scripted devices (needle and
// probe at 50 Hz, breathing marker at 40 Hz, tumour observations at 20 Hz), each tick is timed,
// for each rung r = 8, 16, 32, 64: counters tick_us_* (every tick), tissue_tick_us_* (liver
// step, filter predict and update, look-ahead), needle_tick_us_* (tool poses and breathing
// only) and push_respiratory_us_* (the breathing fit of one marker sample, made on the loop's
// thread too), each as median, p99, p99.9, max and jitter (standard deviation).
// BM_OperatingLoopNeedleTick (r = 16, 64): the same loop stepping the flexible needle (20
// Timoshenko elements, 15 cm) coupled to the reduced liver, inserted at 2 mm/s from 5 mm above
// the capsule (a plane layer over the tumour) down to 35 mm below it, the liver trained also on
// needle-like loads: the needle steps at every tick, the liver steps with its point forces;
// needle_tick then includes the needle's step. Also counted: punctures, the timed ticks with
// needle-tissue flags (needle_flagged_ticks) and the liver steps with flags (tissue_flagged_steps,
// tissue_flags their union).
// BM_OperatingLoopLigamentsNeedleTick (r = 16; 2 x 2 x 2 or 3 x 3 x 3 frames per ligament): the
// needle's loop on the liver hung also by two 100 kPa frame-based ligaments (banded Cholesky),
// stepped with every liver step (tissue_tick includes them; ligament_frames and ligament_nodes
// count them).
// BM_OperatingLoopLadderNeedleTick (r = 16): the needle's loop on a ladder, rung 0 the r modes
// trained without the needle's loads, rung 1 those extended by 8 directions of the needle's training:
// escalation after 5 flagged liver steps, back down after 50 that fit rung 0 (projection residual
// up to 20 %); the insertion starts 2 s later than above. rung_change_tick_us_* times the ticks that
// changed rung after the warm-up; escalations, de_escalations, final_rung and first_rung_change_s
// (the loop time of the first change) count them.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <memory>
#include <numbers>
#include <optional>
#include <random>
#include <vector>

#include "nav/connective/organ_ligaments.hpp"
#include "nav/loop/operating_loop.hpp"
#include "nav/mesh/validation.hpp"
#include "nav/mesher/embedded_liver.hpp"
#include "nav/reduced/reduced_ladder_basis.hpp"
#include "nav/reduced/reduction.hpp"
#include "nav/tissue/tet_fem_model.hpp"

namespace {

using nav::kNsPerMs;
using nav::TimeNs;

constexpr int kTissueEvery = 10;
constexpr double kStepS = 0.01;

/// The embedded liver, its scene (attachments fixed, top boundary a diaphragm) and the tumour centre.
struct Liver {
  nav::EmbeddedLiver liver = nav::make_embedded_liver(nav::kEmbeddedLiverElementSizeM);
  nav::TissueScene scene;
  nav::ObservedPoint tumour;
  double surface_above_tumour_m = -1e9;             ///< the highest boundary node within 5 mm of the tumour's vertical
  std::vector<double> snapshots, needle_snapshots;  ///< training, without and with the needle's loads
  int snapshot_count = 0, needle_snapshot_count = 0;
  Liver() {
    scene.default_material = {5.0e3, 0.45, 1060.0};
    scene.fixed_nodes = liver.attachment_nodes;
    const nav::TetMeshBoundary boundary = nav::extract_boundary(liver.mesh);
    double top_m = -1e9;
    for (const auto& x : liver.mesh.nodes_m) top_m = std::max(top_m, x[2]);
    std::vector<char> on_boundary(liver.mesh.nodes_m.size(), 0);
    for (const std::int32_t node : boundary.mesh_node_of_vertex) on_boundary[static_cast<std::size_t>(node)] = 1;
    const nav::Point3& centre = liver.tumour_centre_m;
    for (std::size_t n = 0; n < liver.mesh.nodes_m.size(); ++n)
      if (on_boundary[n] != 0 &&
          std::hypot(liver.mesh.nodes_m[n][0] - centre[0], liver.mesh.nodes_m[n][1] - centre[1]) < 0.005)
        surface_above_tumour_m = std::max(surface_above_tumour_m, liver.mesh.nodes_m[n][2]);
    for (std::size_t n = 0; n < liver.mesh.nodes_m.size(); ++n)
      if (on_boundary[n] != 0 && liver.mesh.nodes_m[n][2] > top_m - 0.02 &&
          !std::binary_search(liver.attachment_nodes.begin(), liver.attachment_nodes.end(),
                              static_cast<std::int32_t>(n)))
        scene.prescribed_nodes.push_back(static_cast<std::int32_t>(n));
    const auto located = nav::locate_in_tets(liver.mesh, liver.tumour_centre_m, "tumour_centre_m").value();
    tumour = {liver.mesh.tets[static_cast<std::size_t>(located.first)], located.second};
    // Training: full-order quasi-static steps under a gravity ramp and diaphragm moves.
    nav::TissueSolverOptions solver;
    solver.integrator = nav::Integrator::quasi_static;
    solver.cg_iterations = 3;
    const nav::TetFemModel full = nav::make_tet_fem_model(liver.mesh, scene, solver).value();
    auto data = nav::make_tet_fem_data(full).value();
    const auto rest = full.rest_positions_m();
    for (int i = 0; i < 24; ++i) {
      nav::TissueInputs inputs;
      inputs.load_scale = std::min(1.0, 0.25 * (i + 1));
      inputs.prescribed_displacement_m = {0.0, 0.0, 0.01 * std::sin(0.5 * i)};
      nav::step(full, data, inputs);
      if (i % 2 == 1) {
        for (std::size_t k = 0; k < rest.size(); ++k) snapshots.push_back(data.positions_m[k] - rest[k]);
        ++snapshot_count;
      }
    }
    // And, for the needle's loop only, the capsule over the tumour pushed in by up to 1.5 N
    // (its f_p is 1 N) and the shaft's drag at 1 to 4 cm below it, straight and sideways, so
    // that the insertion stays in the envelope.
    needle_snapshots = snapshots;
    needle_snapshot_count = snapshot_count;
    const auto nearest = [&](double depth_m) {
      const Eigen::Vector3d x(centre[0], centre[1], surface_above_tumour_m - depth_m);
      std::int32_t best = 0;
      for (std::size_t n = 0; n < liver.mesh.nodes_m.size(); ++n)
        if ((Eigen::Vector3d(liver.mesh.nodes_m[n].data()) - x).norm() <
            (Eigen::Vector3d(liver.mesh.nodes_m[static_cast<std::size_t>(best)].data()) - x).norm())
          best = static_cast<std::int32_t>(n);
      return best;
    };
    const std::int32_t path[] = {nearest(0.0), nearest(0.01), nearest(0.02), nearest(0.03), nearest(0.04)};
    for (int i = 0; i < 12; ++i) {
      const double f_n = 0.25 * (i % 6 + 1), side_n = i < 6 ? 0.0 : 0.1 * f_n;
      nav::PointForce loads[5];
      for (std::size_t k = 0; k < 5; ++k)
        loads[k] = {path[k], {k % 2 == 0 ? side_n : -side_n, side_n, k == 0 ? -f_n : -0.3 * f_n}};
      nav::TissueInputs inputs;
      inputs.point_forces = loads;
      step(full, data, inputs);
      for (std::size_t k = 0; k < rest.size(); ++k) needle_snapshots.push_back(data.positions_m[k] - rest[k]);
      ++needle_snapshot_count;
    }
  }
};

const Liver& liver() {
  static const Liver built;
  return built;
}

nav::TissueSolverOptions training_solver() {
  nav::TissueSolverOptions solver;
  solver.integrator = nav::Integrator::quasi_static;
  return solver;
}

nav::ReductionOptions reduction(int r) {
  nav::ReductionOptions options;
  options.source = nav::ReducedBasisSource::linear_modes;
  options.force_kind = nav::ReducedForceKind::corotational_cubature;
  options.basis_size = r;
  options.max_cubature_samples = 32;
  return options;
}

/// The needle base's frame in its marker's: the needle points down the marker's -z.
nav::RigidPose needle_marker_from_base() {
  return {Eigen::Vector3d::Zero(),
          Eigen::Quaterniond(Eigen::AngleAxisd(0.5 * std::numbers::pi, Eigen::Vector3d::UnitY()))};
}

/// r vibration modes of the liver with corotational cubature trained on `snapshots`.
nav::ReducedBasis trained_modes(int r, const std::vector<double>& snapshots, int snapshot_count) {
  const Liver& l = liver();
  nav::ReducedBasis basis = nav::make_modal_basis(l.liver.mesh, l.scene, training_solver(), reduction(r)).value();
  if (!nav::add_force_reduction(l.liver.mesh, l.scene, training_solver(), reduction(r), snapshots, snapshot_count,
                                basis)
           .ok())
    std::abort();
  return basis;
}

/// The filter on the tumour of a reduced model of `basis`.
nav::ReducedKalmanModel tumour_filter(const nav::ReducedBasis& basis, const nav::ReducedModel& reduced) {
  nav::ReducedKalmanOptions filter_options;
  filter_options.correction_std = nav::correction_std_from_training(basis, 1.0);
  filter_options.correlation_time_s = 2.0;
  filter_options.gate_chi_square = 1e12;  // every observation is a full update
  const nav::ObservedPoint points[] = {liver().tumour};
  return nav::make_reduced_kalman_model(liver().liver.mesh, basis, reduced, points, filter_options).value();
}

nav::ReducedSolverOptions reduced_options() {
  nav::ReducedSolverOptions options;
  options.step_s = kStepS;
  return options;
}

nav::OperatingLoopOptions loop_options() {
  nav::OperatingLoopOptions o;
  o.tissue_every_ticks = kTissueEvery;
  o.display_latency_ns = 50 * kNsPerMs;
  o.needle_tip_in_marker_m = {0.0, 0.0, -0.15};
  o.diaphragm_per_marker = {0.0, 0.0, 1.0};
  o.respiratory_reference_m = 0.1;
  o.needle.max_extrapolation_ns = 100 * kNsPerMs;
  return o;
}

/// The needle: a plane capsule over the tumour, path points every 5 mm.
nav::OperatingLoopNeedleOptions needle_options() {
  const Liver& l = liver();
  nav::OperatingLoopNeedleOptions needle;
  nav::TissueLayer capsule;
  capsule.surface_point_m = {l.liver.tumour_centre_m[0], l.liver.tumour_centre_m[1], l.surface_above_tumour_m};
  needle.scene.layers = {capsule};
  needle.scene.path_spacing_m = 0.005;
  needle.marker_from_base = needle_marker_from_base();
  return needle;
}

/// The loop of r modes on the liver, optionally with the needle coupled to it.
nav::OperatingLoopModel loop_model(int r, bool with_needle) {
  const Liver& l = liver();
  const nav::ReducedBasis basis = with_needle ? trained_modes(r, l.needle_snapshots, l.needle_snapshot_count)
                                              : trained_modes(r, l.snapshots, l.snapshot_count);
  nav::ReducedModel reduced =
      nav::make_reduced_model(l.liver.mesh, l.scene, training_solver(), basis, reduced_options()).value();
  nav::ReducedKalmanModel filter = tumour_filter(basis, reduced);
  if (!with_needle)
    return nav::make_operating_loop_model(std::move(reduced), std::move(filter), loop_options()).value();
  return nav::make_operating_loop_model(std::move(reduced), std::move(filter), loop_options(), needle_options(),
                                        l.liver.mesh)
      .value();
}

/// The needle's loop of r modes on the liver hung also by two 100 kPa ligaments (3 x 3 x 3 cm,
/// over the right lobe and left of the falciform plane) of n x n x n frames each, solved as a
/// station solves them (banded Cholesky), whose attachment its scene declares.
nav::OperatingLoopModel hung_loop_model(int r, int n) {
  const Liver& l = liver();
  std::vector<nav::LigamentSpec> specs(2);
  specs[0].footprint_centre_m = {-0.045, 0.0, 0.0};
  specs[1].footprint_centre_m = {0.035, 0.015, 0.0};
  for (nav::LigamentSpec& spec : specs) {
    spec.embed_m = 0.006;
    spec.frames = {n, n, n};
  }
  nav::FrameTissueOptions frames;
  frames.step_s = kStepS;
  frames.rayleigh_mass_per_s = 1.0;
  frames.solver = nav::FrameSolver::banded_cholesky;
  auto ligaments = std::make_shared<const nav::OrganLigaments>(
      nav::make_organ_ligaments(l.liver.mesh, specs, {1e5, 0.45, 1100.0}, frames, l.scene.gravity_m_s2).value());
  nav::TissueScene scene = l.scene;
  nav::declare_attachment(ligaments->attachment, scene);
  nav::ReducedBasis basis = nav::make_modal_basis(l.liver.mesh, scene, training_solver(), reduction(r)).value();
  if (!nav::add_force_reduction(l.liver.mesh, scene, training_solver(), reduction(r), l.needle_snapshots,
                                l.needle_snapshot_count, basis)
           .ok())
    std::abort();
  nav::ReducedModel reduced =
      nav::make_reduced_model(l.liver.mesh, scene, training_solver(), basis, reduced_options()).value();
  nav::ReducedKalmanModel filter = tumour_filter(basis, reduced);
  nav::OperatingLoopNeedleOptions needle = needle_options();
  needle.max_point_forces = l.scene.max_point_forces;
  return nav::make_operating_loop_model(std::move(reduced), std::move(filter), loop_options(), needle, l.liver.mesh,
                                        std::move(ligaments))
      .value();
}

/// The needle's loop on a ladder: rung 0 r modes trained without the needle's loads, rung 1
/// those extended by 8 directions of the needle's training (its loads leave rung 0's envelope); the loop
/// escalates after 5 flagged liver steps and steps back down after 50 that fit rung 0.
nav::OperatingLoopModel ladder_loop_model(int r) {
  const Liver& l = liver();
  const nav::ReducedBasis small = trained_modes(r, l.snapshots, l.snapshot_count);
  nav::ReducedBasis big = nav::extend_basis(l.liver.mesh, l.scene, training_solver(), small, r + 8, l.needle_snapshots,
                                            l.needle_snapshot_count)
                              .value();
  if (!nav::add_force_reduction(l.liver.mesh, l.scene, training_solver(), reduction(r + 8), l.needle_snapshots,
                                l.needle_snapshot_count, big)
           .ok())
    std::abort();
  const nav::ReducedRungSpec rungs[] = {{small, reduced_options()}, {big, reduced_options()}};
  nav::ReducedLadderOptions escalation;
  escalation.escalate_after_steps = 5;  // the first steps' transient (from rest, under gravity) stays on rung 0
  escalation.de_escalate_after_steps = 50;
  escalation.de_escalation_residual = 0.2;
  const nav::ReducedLadderModel ladder =
      nav::make_reduced_ladder_model(l.liver.mesh, l.scene, training_solver(), rungs, false, escalation).value();
  std::vector<nav::ReducedKalmanModel> filters{tumour_filter(small, ladder.reduced_rung(0)),
                                               tumour_filter(big, ladder.reduced_rung(1))};
  const nav::OperatingLoopNeedleOptions needle = needle_options();
  return nav::make_operating_loop_model(ladder, std::move(filters), loop_options(), &needle, &l.liver.mesh).value();
}

/// The rigid needle of BM_OperatingLoopTick: 3 cm beside the tumour, moving toward it.
nav::RigidPose needle_beside(TimeNs now) {
  const nav::Point3 tumour = liver().liver.tumour_centre_m;
  const double s = 1e-9 * static_cast<double>(now);
  return {{tumour[0] + 0.03 - 0.003 * s, tumour[1], tumour[2] + 0.15}, Eigen::Quaterniond::Identity()};
}

/// The needle marker of BM_OperatingLoopNeedleTick: the tip from 5 mm above the capsule over
/// the tumour down to 35 mm below it, at 2 mm/s.
nav::RigidPose needle_inserted(TimeNs now) {
  const Liver& l = liver();
  const double lowered_m = std::min(0.002 * 1e-9 * static_cast<double>(now), 0.04);
  const Eigen::Vector3d base_m{l.liver.tumour_centre_m[0], l.liver.tumour_centre_m[1],
                               l.surface_above_tumour_m + 0.155 - lowered_m};
  const nav::RigidPose base_from_marker = nav::inverse(needle_marker_from_base());
  return nav::compose({base_m, needle_marker_from_base().rotation}, base_from_marker);
}

/// Median, p99, p99.9, max and jitter (standard deviation) of `us`, as counters name_us_*.
void report(benchmark::State& state, const std::string& name, std::vector<double>& us) {
  if (us.empty()) return;
  std::sort(us.begin(), us.end());
  const auto quantile = [&](std::size_t per_thousand) {
    return us[std::min(us.size() - 1, (us.size() * per_thousand) / 1000)];
  };
  double sum = 0.0, sum_squares = 0.0;
  for (const double x : us) sum += x, sum_squares += x * x;
  const double mean = sum / static_cast<double>(us.size());
  state.counters[name + "_us_median"] = quantile(500);
  state.counters[name + "_us_p99"] = quantile(990);
  state.counters[name + "_us_p999"] = quantile(999);
  state.counters[name + "_us_max"] = us.back();
  state.counters[name + "_us_jitter"] =
      std::sqrt(std::max(0.0, sum_squares / static_cast<double>(us.size()) - mean * mean));
}

double elapsed_us(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::micro>(std::chrono::steady_clock::now() - start).count();
}

/// Runs the loop on scripted devices (the needle marker at needle_at(t)); after the warm-up,
/// times every tick and marker push.
void run_loop(benchmark::State& state, const nav::OperatingLoopModel& model, nav::RigidPose (*needle_at)(TimeNs)) {
  nav::OperatingLoopData data = nav::make_operating_loop_data(model).value();
  const nav::Point3 tumour = liver().liver.tumour_centre_m;
  std::mt19937_64 rng(5);
  std::normal_distribution<double> noise(0.0, 0.001);
  std::vector<double> tick_us, tissue_us, needle_us, marker_us, rung_change_us;
  int needle_flagged = 0, tissue_flagged = 0;  // timed ticks whose needle-tissue or liver flags were raised
  std::uint32_t tissue_flag_union = 0;
  double first_change_s = -1.0;  // the loop time of the first rung change
  const TimeNs warm_up_ns = 3000 * kNsPerMs;
  TimeNs now = 0;
  const auto one_tick = [&](bool timed) {
    if (now % (20 * kNsPerMs) == 0) {
      nav::push_needle_pose(model, data, {now, needle_at(now)});
      nav::push_probe_pose(model, data,
                           {now, {{tumour[0], tumour[1], tumour[2] + 0.08}, Eigen::Quaterniond::Identity()}});
    }
    if (now % (25 * kNsPerMs) == 0) {
      const double z = 0.1 + 0.006 * std::sin(2.0 * std::numbers::pi * 1e-9 * static_cast<double>(now) / 2.0);
      const auto start = std::chrono::steady_clock::now();
      nav::push_respiratory_sample(model, data, now, {0.0, 0.0, z});
      if (timed) marker_us.push_back(elapsed_us(start));
    }
    if (now % (50 * kNsPerMs) == 0) {
      const nav::Point3 seen = data.outputs.tumour_now_m;
      nav::push_tumour_observation(data, now, {seen[0] + noise(rng), seen[1] + noise(rng), seen[2] + noise(rng)});
    }
    const bool tissue = data.outputs.ticks % kTissueEvery == 0;
    const std::int64_t moves = data.outputs.escalations + data.outputs.de_escalations;
    const auto start = std::chrono::steady_clock::now();
    nav::tick(model, data, now);
    const double us = elapsed_us(start);
    if (data.outputs.escalations + data.outputs.de_escalations != moves) {
      if (first_change_s < 0.0) first_change_s = 1e-9 * static_cast<double>(now);
      if (timed) rung_change_us.push_back(us);
    }
    if (timed) {
      needle_flagged += data.outputs.needle_shape.flags.healthy() ? 0 : 1;
      tissue_flagged += tissue && !data.outputs.tissue.healthy() ? 1 : 0;
      if (tissue) tissue_flag_union |= data.outputs.tissue.bits();
      (tissue ? tissue_us : needle_us).push_back(us);
      tick_us.push_back(us);
    }
    now += kNsPerMs;
    return us;
  };
  while (now < warm_up_ns) one_tick(false);
  for (auto _ : state) state.SetIterationTime(1e-6 * one_tick(true));
  report(state, "tick", tick_us);
  report(state, "tissue_tick", tissue_us);
  report(state, "needle_tick", needle_us);
  report(state, "push_respiratory", marker_us);
  report(state, "rung_change_tick", rung_change_us);
  state.counters["escalations"] = static_cast<double>(data.outputs.escalations);
  state.counters["de_escalations"] = static_cast<double>(data.outputs.de_escalations);
  state.counters["final_rung"] = data.outputs.liver_rung;
  state.counters["first_rung_change_s"] = first_change_s;
  state.counters["degraded"] = data.outputs.degraded ? 1.0 : 0.0;
  state.counters["tissue_flags"] = tissue_flag_union;  // raised on any timed liver step
  state.counters["tissue_flagged_steps"] = static_cast<double>(tissue_flagged);
  state.counters["lookahead_steps"] = model.lookahead_steps;
  state.counters["punctures"] = data.outputs.needle_shape.punctures;
  state.counters["needle_flagged_ticks"] = static_cast<double>(needle_flagged);
}

void BM_OperatingLoopTick(benchmark::State& state) {
  run_loop(state, loop_model(static_cast<int>(state.range(0)), false), needle_beside);
}

void BM_OperatingLoopNeedleTick(benchmark::State& state) {
  run_loop(state, loop_model(static_cast<int>(state.range(0)), true), needle_inserted);
}

void BM_OperatingLoopLigamentsNeedleTick(benchmark::State& state) {
  const nav::OperatingLoopModel model =
      hung_loop_model(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
  state.counters["ligament_frames"] = static_cast<double>(model.ligaments->model.frame_count());
  state.counters["ligament_nodes"] = static_cast<double>(model.ligaments->attachment.nodes.size());
  run_loop(state, model, needle_inserted);
}

/// The same insertion 2 s later, so that it leaves rung 0's envelope after the warm-up.
nav::RigidPose needle_inserted_later(TimeNs now) { return needle_inserted(std::max<TimeNs>(0, now - 2000 * kNsPerMs)); }

void BM_OperatingLoopLadderNeedleTick(benchmark::State& state) {
  run_loop(state, ladder_loop_model(static_cast<int>(state.range(0))), needle_inserted_later);
}

BENCHMARK(BM_OperatingLoopTick)
    ->Arg(8)
    ->Arg(16)
    ->Arg(32)
    ->Arg(64)
    ->UseManualTime()
    ->Unit(benchmark::kMicrosecond)
    ->Iterations(20000);
BENCHMARK(BM_OperatingLoopNeedleTick)
    ->Arg(16)
    ->Arg(64)
    ->UseManualTime()
    ->Unit(benchmark::kMicrosecond)
    ->Iterations(20000);
BENCHMARK(BM_OperatingLoopLigamentsNeedleTick)
    ->Args({16, 2})
    ->Args({16, 3})
    ->UseManualTime()
    ->Unit(benchmark::kMicrosecond)
    ->Iterations(20000);
BENCHMARK(BM_OperatingLoopLadderNeedleTick)->Arg(16)->UseManualTime()->Unit(benchmark::kMicrosecond)->Iterations(20000);

}  // namespace
