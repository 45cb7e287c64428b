#include "nav/station/station_liver.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

#include <Eigen/Geometry>

#include "nav/connective/organ_attachment.hpp"
#include "nav/mesh/validation.hpp"
#include "nav/mesher/embedded_liver.hpp"
#include "nav/reduced/reduction.hpp"
#include "nav/tissue/tet_fem_model.hpp"

namespace nav::station {

namespace {

constexpr double kDiaphragmDepthM = 0.02;     // boundary nodes this close to the top are the diaphragm
constexpr int kTrainingSteps = 24;            // full-order quasi-static steps under diaphragm moves
constexpr double kTrainingDiaphragmM = 0.012; // their amplitude (beyond the demo's breathing)

Error liver_error(const Scene& scene, const std::string& message, const std::string& field) {
  return Error{message, scene.source_path, scene.liver.line, field};
}

/// Boundary nodes within kDiaphragmDepthM of the top that are not attachments.
std::vector<std::int32_t> diaphragm_nodes(const TetMesh& mesh, const std::vector<std::int32_t>& attachments) {
  const TetMeshBoundary boundary = extract_boundary(mesh);
  double top_m = -1e9;
  for (const auto& x : mesh.nodes_m) top_m = std::max(top_m, x[2]);
  std::vector<char> on_boundary(mesh.nodes_m.size(), 0);
  for (const std::int32_t node : boundary.mesh_node_of_vertex) on_boundary[static_cast<std::size_t>(node)] = 1;
  std::vector<std::int32_t> nodes;
  for (std::size_t n = 0; n < mesh.nodes_m.size(); ++n)
    if (on_boundary[n] != 0 && mesh.nodes_m[n][2] > top_m - kDiaphragmDepthM &&
        !std::binary_search(attachments.begin(), attachments.end(), static_cast<std::int32_t>(n)))
      nodes.push_back(static_cast<std::int32_t>(n));
  return nodes;
}

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

}  // namespace

Result<StationLiver> make_station_liver(const Scene& scene) {
  if (scene.liver.mesh.source != LiverMeshSource::generated)
    return liver_error(scene, "a running station simulates the generated liver only", "liver.mesh");
  StationLiver liver;
  std::vector<std::int32_t> attachments;
  try {
    EmbeddedLiver generated = make_embedded_liver(scene.liver.mesh.element_size_m);
    liver.mesh = std::move(generated.mesh);
    liver.tumour_m = generated.tumour_centre_m;
    attachments = std::move(generated.attachment_nodes);
  } catch (const std::invalid_argument& e) {
    return liver_error(scene, e.what(), "liver.mesh.element_size_m");
  }
  if (scene.liver.tumour_m) liver.tumour_m = *scene.liver.tumour_m;
  const auto located = locate_in_tets(liver.mesh, liver.tumour_m, "tumour_m");
  if (!located.ok()) return liver_error(scene, "the tumour point lies outside the liver mesh", "liver.tumour_m");
  liver.tumour = {liver.mesh.tets[static_cast<std::size_t>(located.value().first)], located.value().second};
  liver.scene.default_material = scene.liver.material;
  liver.scene.gravity_m_s2 = {0.0, 0.0, 0.0};
  liver.scene.fixed_nodes = attachments;
  liver.scene.prescribed_nodes = diaphragm_nodes(liver.mesh, attachments);
  return liver;
}

RigidPose needle_base_in_marker() {
  return {Eigen::Vector3d::Zero(), Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitX(), -Eigen::Vector3d::UnitZ())};
}

Result<OperatingLoopModel> make_station_loop(const StationLiver& liver, const Scene& scene, const BreathingGeometry& breathing,
                                             const StationLoopSettings& settings) {
  const StationSettings& station = scene.station;
  const double step_s = 1.0 / station.tissue_rate_hz;
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
  const Status trained = add_force_reduction(liver.mesh, liver.scene, solver, reduction, snapshots.value(), snapshot_count, basis.value());
  if (!trained.ok()) return trained.error();
  ReducedSolverOptions reduced_options;
  reduced_options.step_s = step_s;
  auto reduced = make_reduced_model(liver.mesh, liver.scene, solver, basis.value(), reduced_options);
  if (!reduced.ok()) return reduced.error();
  ReducedKalmanOptions filter_options;
  filter_options.correction_std = correction_std_from_training(basis.value(), settings.correction_fraction);
  filter_options.correlation_time_s = settings.correlation_time_s;
  filter_options.gate_chi_square = settings.gate_chi_square;
  filter_options.observation_std_m = std::max(scene.devices.ultrasound.target_noise_m, 1e-4);
  const ObservedPoint points[] = {liver.tumour};
  auto filter = make_reduced_kalman_model(liver.mesh, basis.value(), reduced.value(), points, filter_options);
  if (!filter.ok()) return filter.error();

  OperatingLoopOptions o;
  o.tick_period_ns = static_cast<TimeNs>(std::llround(1e9 / station.loop_rate_hz));
  o.tissue_every_ticks = static_cast<int>(std::lround(station.loop_rate_hz / station.tissue_rate_hz));
  o.display_latency_ns = static_cast<TimeNs>(std::llround(station.display_latency_ms * 1e6));
  const double needle_length_m = scene.needle ? scene.needle->parameters.length_m : 0.15;
  o.needle_tip_in_marker_m = {0.0, 0.0, -needle_length_m};
  o.diaphragm_per_marker = breathing.diaphragm_per_marker;
  o.respiratory_reference_m = breathing.marker_rest_m[2];
  o.needle.max_extrapolation_ns = settings.needle_max_extrapolation_ns;
  o.probe.max_extrapolation_ns = settings.needle_max_extrapolation_ns;
  // The breathing fit's window (8 s) at the tracker's rate, and some.
  o.breathing.history_capacity = static_cast<std::size_t>(std::ceil(scene.devices.tracker.rate_hz * 8.0)) + 16;
  if (!scene.needle) return make_operating_loop_model(std::move(reduced).value(), std::move(filter).value(), o);
  OperatingLoopNeedleOptions needle;
  needle.parameters = scene.needle->parameters;
  needle.scene = scene.needle->interaction;
  needle.base_in_marker = needle_base_in_marker();
  needle.max_point_forces = liver.scene.max_point_forces;
  auto loop = make_operating_loop_model(std::move(reduced).value(), std::move(filter).value(), o, needle, liver.mesh);
  if (!loop.ok()) return Error{loop.error().describe(), scene.source_path, scene.needle->line, "needle"};
  return loop;
}

}  // namespace nav::station
