#include "station_liver_loop.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "nav/connective/organ_attachment.hpp"
#include "nav/mesh/validation.hpp"
#include "nav/mesher/embedded_liver.hpp"
#include "nav/reduced/reduced_model.hpp"
#include "nav/reduced/reduction.hpp"
#include "nav/tissue/tet_fem_model.hpp"

namespace embedding {

namespace {

constexpr double kDiaphragmDepthM = 0.02;  // boundary nodes this close to the top are the diaphragm
constexpr int kSolvesPerLift = 3;          // quasi-static corotational steps to converge at one lift

/// Boundary nodes within kDiaphragmDepthM of the top (z) that are not attachments.
std::vector<std::int32_t> diaphragm_nodes(const nav::TetMesh& mesh, const std::vector<std::int32_t>& attachments) {
  double top_m = -1e9;
  for (const nav::Point3& x : mesh.nodes_m) top_m = std::max(top_m, x[2]);
  std::vector<std::int32_t> nodes;
  for (const std::int32_t node : nav::extract_boundary(mesh).mesh_node_of_vertex)
    if (mesh.nodes_m[static_cast<std::size_t>(node)][2] > top_m - kDiaphragmDepthM &&
        !std::binary_search(attachments.begin(), attachments.end(), node))
      nodes.push_back(node);
  std::sort(nodes.begin(), nodes.end());
  nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
  return nodes;
}

/// The full-order model's quasi-static displacements (3 per node, from rest) at each lift of
/// `lifts_m` in turn, each converged by kSolvesPerLift steps: column-major snapshots.
nav::Result<std::vector<double>> full_order_states(const Liver& liver, const std::vector<double>& lifts_m) {
  nav::TissueSolverOptions solver;
  solver.integrator = nav::Integrator::quasi_static;
  auto model = nav::make_tet_fem_model(liver.mesh, liver.scene, solver);
  if (!model.ok()) return model.error();
  auto data = nav::make_tet_fem_data(model.value());
  if (!data.ok()) return data.error();
  const auto rest = model.value().rest_positions_m();
  std::vector<double> states;
  states.reserve(rest.size() * lifts_m.size());
  for (const double lift_m : lifts_m) {
    nav::TissueInputs inputs;
    inputs.prescribed_displacement_m = {0.0, 0.0, lift_m};
    for (int i = 0; i < kSolvesPerLift; ++i) nav::step(model.value(), data.value(), inputs);
    for (std::size_t k = 0; k < rest.size(); ++k) states.push_back(data.value().positions_m[k] - rest[k]);
  }
  return states;
}

}  // namespace

nav::Result<Liver> make_liver(double element_size_m) {
  nav::EmbeddedLiver generated = nav::make_embedded_liver(element_size_m);
  Liver liver;
  liver.mesh = std::move(generated.mesh);
  const auto located = nav::locate_in_tets(liver.mesh, generated.tumour_centre_m, "tumour");
  if (!located.ok()) return located.error();
  liver.tumour = {liver.mesh.tets[static_cast<std::size_t>(located.value().first)], located.value().second};
  liver.tumour_rest_m = {generated.tumour_centre_m[0], generated.tumour_centre_m[1], generated.tumour_centre_m[2]};
  liver.scene.default_material = {5000.0, 0.45, 1060.0};
  liver.scene.gravity_m_s2 = {0.0, 0.0, 0.0};
  liver.scene.fixed_nodes = generated.attachment_nodes;
  liver.scene.prescribed_nodes = diaphragm_nodes(liver.mesh, liver.scene.fixed_nodes);
  return liver;
}

nav::Result<TumourTruth> TumourTruth::solve(const Liver& liver, double max_lift_m, int count) {
  TumourTruth truth;
  truth.min_m_ = -max_lift_m;
  truth.step_m_ = 2.0 * max_lift_m / (count - 1);
  std::vector<double> lifts_m;
  for (int i = 0; i < count; ++i) lifts_m.push_back(truth.min_m_ + i * truth.step_m_);
  auto states = full_order_states(liver, lifts_m);
  if (!states.ok()) return states.error();
  const std::size_t dofs = 3 * liver.mesh.nodes_m.size();
  for (int i = 0; i < count; ++i) {
    Eigen::Vector3d p = liver.tumour_rest_m;
    for (int c = 0; c < 4; ++c)
      for (int a = 0; a < 3; ++a)
        p[a] += liver.tumour.weights[static_cast<std::size_t>(c)] *
                states.value()[static_cast<std::size_t>(i) * dofs +
                               3 * static_cast<std::size_t>(liver.tumour.nodes[static_cast<std::size_t>(c)]) +
                               static_cast<std::size_t>(a)];
    truth.tumour_m_.push_back(p);
  }
  return truth;
}

Eigen::Vector3d TumourTruth::at(double lift_m) const {
  const double s = std::clamp((lift_m - min_m_) / step_m_, 0.0, static_cast<double>(tumour_m_.size() - 1));
  const auto i = std::min(static_cast<std::size_t>(s), tumour_m_.size() - 2);
  const double f = s - static_cast<double>(i);
  return (1.0 - f) * tumour_m_[i] + f * tumour_m_[i + 1];
}

nav::Result<nav::OperatingLoopModel> make_loop(const Liver& liver, const LoopSettings& settings) {
  const double step_s = 1e-9 * static_cast<double>(settings.tick_period_ns * settings.tissue_every_ticks);
  nav::ReductionOptions reduction;
  reduction.source = nav::ReducedBasisSource::linear_modes;
  reduction.force_kind = nav::ReducedForceKind::corotational_cubature;
  reduction.basis_size = 16;
  reduction.max_cubature_samples = 32;
  nav::TissueSolverOptions solver;
  solver.integrator = nav::Integrator::quasi_static;
  auto basis = nav::make_modal_basis(liver.mesh, liver.scene, solver, reduction);
  if (!basis.ok()) return basis.error();
  // Training: full-order quasi-static states at lifts up to 12 mm (beyond the breathing).
  const std::vector<double> training_lifts_m{-0.012, -0.008, -0.004, 0.004, 0.008, 0.012, 0.002, -0.006, 0.010, -0.010};
  auto snapshots = full_order_states(liver, training_lifts_m);
  if (!snapshots.ok()) return snapshots.error();
  const nav::Status trained = nav::add_force_reduction(liver.mesh, liver.scene, solver, reduction, snapshots.value(),
                                                       static_cast<int>(training_lifts_m.size()), basis.value());
  if (!trained.ok()) return trained.error();
  nav::ReducedSolverOptions reduced_options;
  reduced_options.step_s = step_s;
  auto reduced = nav::make_reduced_model(liver.mesh, liver.scene, solver, basis.value(), reduced_options);
  if (!reduced.ok()) return reduced.error();
  // The filter's correction: 3 times the modes' training envelope, correlated over 2 s.
  nav::ReducedKalmanOptions filter_options;
  filter_options.correction_std = nav::correction_std_from_training(basis.value(), 3.0);
  filter_options.correlation_time_s = 2.0;
  filter_options.observation_std_m = settings.observation_std_m;
  const nav::ObservedPoint points[] = {liver.tumour};
  auto filter = nav::make_reduced_kalman_model(liver.mesh, basis.value(), reduced.value(), points, filter_options);
  if (!filter.ok()) return filter.error();

  nav::OperatingLoopOptions o;
  o.tick_period_ns = settings.tick_period_ns;
  o.tissue_every_ticks = settings.tissue_every_ticks;
  o.display_latency_ns = settings.display_latency_ns;
  o.needle_tip_in_marker_m = {0.0, 0.0, -settings.needle_length_m};
  o.diaphragm_per_marker = {0.0, 0.0, 1.0};
  o.respiratory_reference_m = settings.respiratory_reference_m;
  o.needle.max_extrapolation_ns = 100 * nav::kNsPerMs;  // the display latency plus the tracker's delay
  o.probe.max_extrapolation_ns = 100 * nav::kNsPerMs;
  o.breathing.history_capacity =
      static_cast<std::size_t>(std::ceil(settings.tracker_rate_hz * 8.0)) + 16;  // the 8 s fit window
  return nav::make_operating_loop_model(std::move(reduced).value(), std::move(filter).value(), o);
}

}  // namespace embedding
