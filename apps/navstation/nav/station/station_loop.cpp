#include "nav/station/station_loop.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include <Eigen/Geometry>

#include "nav/reduced/reduction.hpp"
#include "nav/station/scene_frames.hpp"
#include "nav/station/station_build.hpp"
#include "nav/station/station_needle_surfaces.hpp"
#include "nav/station/tracker_registration.hpp"
#include "nav/tissue/tet_fem_model.hpp"

namespace nav::station {

namespace {

constexpr int kTrainingSteps = 24;                // full-order quasi-static steps under diaphragm moves
constexpr double kTrainingDiaphragmM = 0.012;     // their amplitude (beyond the demo's breathing)
constexpr double kNeedleLengthToleranceM = 1e-3;  // the URDF's base-to-tip distance against the scene's needle length

/// Displacement snapshots of full-order quasi-static steps under diaphragm moves.
Result<std::vector<double>> training_snapshots(const StationLiver& liver, int& count) {
  TissueSolverOptions solver;
  solver.integrator = Integrator::quasi_static;
  solver.cg_iterations = 3;
  auto full = make_tet_fem_model(liver.mesh, liver.scene, solver);
  if (!full.ok()) return full.error();
  auto data = make_tet_fem_data(full.value());
  if (!data.ok()) return data.error();
  const auto rest = full.value().rest_positions_m();
  std::vector<double> snapshots;
  count = 0;
  for (int i = 0; i < kTrainingSteps; ++i) {
    TissueInputs inputs;
    inputs.prescribed_displacement_m = {0.0, 0.0, kTrainingDiaphragmM * std::sin(0.5 * i)};
    step(full.value(), data.value(), inputs);
    if (i % 2 == 1) {
      for (std::size_t k = 0; k < rest.size(); ++k) snapshots.push_back(data.value().positions_m[k] - rest[k]);
      ++count;
    }
  }
  return snapshots;
}

/// The reduced basis trained at start-up on the full-order liver (a full-order rung).
Result<ReducedRungSpec> trained_rung(const StationLiver& liver, const Scene& scene,
                                     const StationLoopSettings& settings) {
  ReductionOptions reduction;
  reduction.source = ReducedBasisSource::linear_modes;
  reduction.force_kind = ReducedForceKind::corotational_cubature;
  reduction.basis_size = settings.basis_size;
  reduction.max_cubature_samples = settings.max_cubature_samples;
  TissueSolverOptions solver;
  solver.integrator = Integrator::quasi_static;
  auto basis = make_modal_basis(liver.mesh, liver.scene, solver, reduction);
  if (!basis.ok()) return basis.error();
  int snapshot_count = 0;
  auto snapshots = training_snapshots(liver, snapshot_count);
  if (!snapshots.ok()) return snapshots.error();
  const Status trained =
      add_force_reduction(liver.mesh, liver.scene, solver, reduction, snapshots.value(), snapshot_count, basis.value());
  if (!trained.ok()) return trained.error();
  ReducedSolverOptions reduced;
  reduced.step_s = 1.0 / scene.station.tissue_rate_hz;
  return ReducedRungSpec{std::move(basis).value(), reduced};
}

/// The full-order liver whose static compliance the loop's needle meets beyond its reduced
/// liver's: quasi-static, with the rest LDL^T factor, its point forces spread as the scene's
/// needle says.
Result<TetFemModel> static_full_order_liver(const StationLiver& liver, const NeedleSettings& needle) {
  TissueSolverOptions solver;
  solver.integrator = Integrator::quasi_static;
  solver.solver = LinearSolver::ldlt_warped;
  TissueScene spread = liver.scene;
  spread.point_force_own_share = needle.point_force_own_share;
  return make_tet_fem_model(liver.mesh, spread, solver);
}

OperatingLoopOptions loop_options(const Scene& scene, const BreathingGeometry& breathing,
                                  const NeedleCalibration& needle, const StationLoopSettings& settings) {
  const StationSettings& station = scene.station;
  OperatingLoopOptions o;
  o.tick_period_ns = static_cast<TimeNs>(std::llround(1e9 / station.loop_rate_hz));
  o.tissue_every_ticks = static_cast<int>(std::lround(station.loop_rate_hz / station.tissue_rate_hz));
  o.display_latency_ns = static_cast<TimeNs>(std::llround(station.display_latency_ms * 1e6));
  o.needle_tip_in_marker_m = needle.tip_in_marker_m;
  o.diaphragm_per_marker = breathing.diaphragm_per_marker;
  o.respiratory_reference_m = breathing.marker_rest_m[2];
  o.needle.max_extrapolation_ns = settings.needle_max_extrapolation_ns;
  o.probe.max_extrapolation_ns = settings.needle_max_extrapolation_ns;
  o.needle.fit_window_ns = o.probe.fit_window_ns =
      static_cast<TimeNs>(std::llround(scene.devices.tracker.fit_window_ms * 1e6));
  // The breathing fit's window (8 s) at the tracker's rate, and some.
  o.breathing.history_capacity = static_cast<std::size_t>(std::ceil(scene.devices.tracker.rate_hz * 8.0)) + 16;
  return o;
}

/// The filter on the tumour of rung `k` (0: liver.model.artifact, k: escalation.rungs[k - 1]);
/// errors at that key. Its correction is sized by the artifact's training envelope.
Result<ReducedKalmanModel> tumour_filter(const StationLiver& liver, const Scene& scene, std::size_t k,
                                         const ReducedBasis& basis, const ReducedModel& reduced,
                                         const StationLoopSettings& settings) {
  const auto at_artifact = [&](const std::string& message) {
    if (k == 0)
      return Error{
          .message = message, .file = scene.source_path, .line = scene.liver.line, .field = "liver.model.artifact"};
    return Error{.message = message,
                 .file = scene.source_path,
                 .line = scene.liver.escalation->rungs[k - 1].line,
                 .field = "liver.model.escalation.rungs[" + std::to_string(k - 1) + "]"};
  };
  if (basis.training_q_bound.empty() && scene.liver.rung == LiverRung::reduced)
    return at_artifact(
        "the artifact has no training envelope (a basis made without training loads); the station's filter sizes "
        "its correction by it: make the artifact with navtool reduce");
  ReducedKalmanOptions options;
  options.correction_std = correction_std_from_training(basis, settings.correction_fraction);
  options.correlation_time_s = settings.correlation_time_s;
  options.gate_chi_square = settings.gate_chi_square;
  options.observation_std_m = std::max(scene.devices.ultrasound.target_noise_m, 1e-4);
  const ObservedPoint points[] = {liver.tumour};
  auto filter = make_reduced_kalman_model(liver.mesh, basis, reduced, points, options);
  if (!filter.ok()) return at_artifact(filter.error().describe());
  return filter;
}

/// The rungs' filters and the loop on the scene's ladder.
Result<OperatingLoopModel> ladder_loop(const StationLiver& liver, const Scene& scene,
                                       std::span<const ReducedRungSpec> rungs, const OperatingLoopOptions& o,
                                       const OperatingLoopNeedleOptions* needle, const StationLoopSettings& settings,
                                       std::shared_ptr<const OrganLigaments> ligaments) {
  auto ladder = make_scene_ladder(scene, liver.mesh, liver.scene, rungs);
  if (!ladder.ok()) return ladder.error();
  std::vector<ReducedKalmanModel> filters;
  for (std::size_t k = 0; k < rungs.size(); ++k) {
    auto filter =
        tumour_filter(liver, scene, k, rungs[k].basis, ladder.value().reduced_rung(static_cast<int>(k)), settings);
    if (!filter.ok()) return filter.error();
    filters.push_back(std::move(filter).value());
  }
  return make_operating_loop_model(ladder.value(), std::move(filters), o, needle, &liver.mesh, std::move(ligaments));
}

/// The loop on `liver` (see make_station_loop), hung by `ligaments` when not null (their
/// attachment declared in liver.scene, beside the needle's point forces).
Result<OperatingLoopModel> loop_on(const StationLiver& liver, const Scene& scene, const BreathingGeometry& breathing,
                                   const StationLoopSettings& settings,
                                   std::shared_ptr<const OrganLigaments> ligaments) {
  auto calibration = scene_needle_calibration(scene);
  if (!calibration.ok()) return calibration.error();
  const OperatingLoopOptions o = loop_options(scene, breathing, calibration.value(), settings);
  std::optional<OperatingLoopNeedleOptions> needle;
  std::optional<TetFemModel> missing_compliance_source;
  if (scene.needle) {
    auto interaction = station_needle_interaction(scene, liver.mesh, liver.tumour_m);
    if (!interaction.ok()) return interaction.error();
    needle.emplace();
    needle->parameters = scene.needle->parameters;
    needle->scene = std::move(interaction).value();
    needle->marker_from_base = calibration.value().marker_from_base;
    needle->max_point_forces = liver.scene.max_point_forces - (ligaments ? ligaments->attachment.nodes.size() : 0);
    if (scene.needle->missing_compliance_radius_m > 0.0) {
      auto full = static_full_order_liver(liver, *scene.needle);
      if (!full.ok())
        return Error{.message = full.error().describe(),
                     .file = scene.source_path,
                     .line = scene.needle->line,
                     .field = "needle.missing_compliance_radius_m"};
      missing_compliance_source.emplace(std::move(full).value());
      needle->missing_compliance_source = &*missing_compliance_source;
      needle->missing_compliance_radius_m = scene.needle->missing_compliance_radius_m;
    }
  }
  const auto loop_error = [&](const Error& e) {  // the loop's own errors: its needle's, or the liver model's
    return e.file.empty() ? Error{.message = e.describe(),
                                  .file = scene.source_path,
                                  .line = needle ? scene.needle->line : scene.liver.line,
                                  .field = needle ? "needle" : "liver.model"}
                          : e;
  };
  std::vector<ReducedRungSpec> rungs;
  if (scene.liver.rung == LiverRung::full) {
    auto trained = trained_rung(liver, scene, settings);
    if (!trained.ok())
      return Error{.message = trained.error().describe(),
                   .file = scene.source_path,
                   .line = scene.liver.line,
                   .field = "liver.model (start-up training)"};
    rungs.push_back(std::move(trained).value());
  } else {
    auto loaded = load_reduced_rungs(scene, liver.mesh);
    if (!loaded.ok()) return loaded.error();
    rungs = std::move(loaded).value();
  }
  if (scene.liver.escalation) {
    auto loop = ladder_loop(liver, scene, rungs, o, needle ? &*needle : nullptr, settings, std::move(ligaments));
    if (!loop.ok()) return loop_error(loop.error());
    return loop;
  }
  auto reduced = make_scene_reduced_model(scene, liver.mesh, liver.scene, rungs.front());
  if (!reduced.ok()) return reduced.error();
  auto filter = tumour_filter(liver, scene, 0, rungs.front().basis, reduced.value(), settings);
  if (!filter.ok()) return filter.error();
  auto loop = needle ? make_operating_loop_model(std::move(reduced).value(), std::move(filter).value(), o, *needle,
                                                 liver.mesh, std::move(ligaments))
                     : make_operating_loop_model(std::move(reduced).value(), std::move(filter).value(), o,
                                                 std::move(ligaments));
  if (!loop.ok()) return loop_error(loop.error());
  return loop;
}

}  // namespace

RigidPose needle_marker_from_base() {
  return {Eigen::Vector3d::Zero(),
          Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitX(), -Eigen::Vector3d::UnitZ())};
}

Status check_station_loop(const Scene& scene) {
  if (scene.liver.escalation && scene.liver.escalation->full_order_on_top)
    return Error{
        .message =
            "a running station's ladder has reduced rungs only (its filter needs reduced coordinates on every rung): "
            "set full_order_on_top: false",
        .file = scene.source_path,
        .line = scene.liver.escalation->line,
        .field = "liver.model.escalation.full_order_on_top"};
  if (auto registration = scene_reference_from_model(scene); !registration.ok()) return registration.error();
  return Done{};
}

Result<NeedleCalibration> scene_needle_calibration(const Scene& scene) {
  const auto urdf_error = [&](const std::string& message) {
    return Error{.message = message, .file = scene.source_path, .line = scene.frames.line, .field = "frames.urdf"};
  };
  auto base = scene_fixed_chain(scene, "needle_marker", "needle_base");
  if (!base.ok()) return base.error();
  auto tip = scene_fixed_chain(scene, "needle_marker", "needle_tip");
  if (!tip.ok()) return tip.error();
  const Eigen::Vector3d base_m = base.value().translation();
  const Eigen::Vector3d tip_m = tip.value().translation();
  const double length_m = (tip_m - base_m).norm();
  if (length_m < 1e-3)
    return urdf_error("the needle's tip is at its base (needle_base_to_tip: run navtool calib pivot)");
  if (scene.needle && std::abs(length_m - scene.needle->parameters.length_m) > kNeedleLengthToleranceM) {
    char text[256];
    std::snprintf(text, sizeof text, "the URDF's needle is %.1f mm from base to tip (%s), the scene's %.1f mm long",
                  1e3 * length_m, scene.frames.urdf_path.c_str(), 1e3 * scene.needle->parameters.length_m);
    return Error{.message = text, .file = scene.source_path, .line = scene.needle->line, .field = "needle.length_m"};
  }
  NeedleCalibration calibration;
  calibration.marker_from_base = {base_m, Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitX(), tip_m - base_m)};
  calibration.tip_in_marker_m = tip_m;
  return calibration;
}

Result<OperatingLoopModel> make_station_loop(const StationLiver& liver, const Scene& scene,
                                             const BreathingGeometry& breathing, const StationLoopSettings& settings) {
  if (const Status runnable = check_station_loop(scene); !runnable.ok()) return runnable.error();
  if (!scene.ligaments) return loop_on(liver, scene, breathing, settings, nullptr);
  StationLiver hung = liver;  // the liver's scene with the ligaments' attachment declared
  auto ligaments = make_scene_ligaments(scene, hung.mesh, hung.scene);
  if (!ligaments.ok()) return ligaments.error();
  return loop_on(hung, scene, breathing, settings,
                 std::make_shared<const OrganLigaments>(std::move(ligaments).value()));
}

std::string describe_station_loop(const Scene& scene, const OperatingLoopModel& loop) {
  const auto rung_text = [](const ReducedModel& r) {
    return "r = " + std::to_string(r.basis_size()) + " (" + std::to_string(r.sample_count()) + " sampled tetrahedra)";
  };
  const ReducedModel& base = loop.rungs.front().reduced;
  std::string text;
  if (scene.liver.rung == LiverRung::full) {
    text = "liver model: the scene's rung is full order; the loop runs a reduced liver trained on it at start-up, " +
           rung_text(base) + " (vibration modes, corotational cubature on diaphragm moves)";
  } else {
    text = "liver model: reduced " + rung_text(base) + " from " + scene.liver.reduced_artifact_path;
    for (std::size_t k = 1; k < loop.rungs.size(); ++k)
      text += "; rung " + std::to_string(k) + ": " + rung_text(loop.rungs[k].reduced) + " from " +
              scene.liver.escalation->rungs[k - 1].artifact_path;
  }
  if (loop.ligaments)
    text += "; hung by " + std::to_string(loop.ligaments->grids.size()) + " ligaments (" +
            std::to_string(loop.ligaments->model.frame_count()) + " frames on " +
            std::to_string(loop.ligaments->attachment.nodes.size()) + " liver nodes), stepped with it";
  return text;
}

}  // namespace nav::station
