// The reduced liver's online error estimate (error_calibration.hpp) on the liver at about 1000
// tetrahedra, its POD basis (r = 24, corotational cubature) trained on gravity, the diaphragm and
// the probe pushes and needle forces of one side of the liver only (x below the median of the
// pushes). Calibrated on the held-out loads of that side; checked: the estimate's correlation
// with the true largest nodal error and its ratio band there, and on the training loads; a
// probe push on the other side, where training did not reach, keeps every |q_i|
// inside the training envelope while its error is several times the trained side's: the
// estimate fires, a ladder topped by the full order escalates on it, and the error after
// escalation is below a quarter of the error before (both against the full order's static
// solution); the step with the estimate and the scene's most point forces never allocates.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>

#include <Eigen/SparseCholesky>

#include "nav/reduced/error_calibration.hpp"
#include "nav/reduced/full_system.hpp"
#include "nav/reduced/reduced_ladder.hpp"
#include "nav/reduced/reduction.hpp"
#include "nav/tissue/liver_scenes.hpp"
#include "support/allocation_guard.hpp"
#include "support/test_data.hpp"

namespace nav {
namespace {

/// The x of a load's first point force (its patch's centre).
double load_x(const TetMesh& mesh, const TrainingLoad& load) {
  return mesh.nodes_m[static_cast<std::size_t>(load.point_forces.front().node)][0];
}

/// The trained liver, its calibration and the loads of both sides.
struct Trained {
  TetMesh mesh;
  TissueScene scene;
  double split_x = 0.0;
  ReducedBasis basis;
  ErrorCalibrationReport report;
  std::vector<TrainingLoad> trained_side, untrained_side;  ///< held-out loads with point forces
  std::vector<TrainingLoad> training;                      ///< what the basis was trained on
  std::vector<TrainingLoad> calibration;                   ///< the trained side's held-out loads
  std::vector<std::vector<double>> calibration_full_m;     ///< their full-order solutions
};

/// Loads without point forces, and those whose first force lies on the trained side.
std::vector<TrainingLoad> one_side(const TetMesh& mesh, const std::vector<TrainingLoad>& loads, double split_x,
                                   bool trained) {
  std::vector<TrainingLoad> kept;
  for (const TrainingLoad& load : loads) {
    if (load.point_forces.empty()) {
      if (trained) kept.push_back(load);
      continue;
    }
    if ((load_x(mesh, load) < split_x) == trained) kept.push_back(load);
  }
  return kept;
}

std::vector<std::vector<double>> full_order_solutions(const Trained& t, std::span<const TrainingLoad> loads) {
  StaticSolveOptions options;
  options.snapshot_fractions = {1.0};
  options.threads = 2;
  std::vector<std::vector<double>> out;
  for (const auto& solved : solve_each_static_load(t.mesh, t.scene, loads, options)) {
    EXPECT_TRUE(solved.ok()) << solved.error().describe();
    out.push_back(solved.ok() ? solved.value().displacements_m : std::vector<double>{});
  }
  return out;
}

const Trained* trained() {
  static const std::unique_ptr<Trained> instance = [] {
    const std::string dir = testing::shared_data_path("liver");
    if (!testing::file_exists(dir + "/liverFine.vtu")) return std::unique_ptr<Trained>();
    auto t = std::make_unique<Trained>();
    t->mesh = load_liver_mesh(dir, 1000).value();
    t->scene = liver_reduction_scene(t->mesh);
    TrainingLoadOptions options;
    options.probe_pushes = 16;
    options.needle_forces = 12;
    const auto training = make_training_loads(t->mesh, t->scene, options, LoadSet::training);
    std::vector<double> push_x;
    for (const TrainingLoad& load : training)
      if (load.name.starts_with("push")) push_x.push_back(load_x(t->mesh, load));
    std::nth_element(push_x.begin(), push_x.begin() + static_cast<std::ptrdiff_t>(push_x.size() / 2), push_x.end());
    t->split_x = push_x[push_x.size() / 2];
    t->training = one_side(t->mesh, training, t->split_x, true);
    StaticSolveOptions solve;
    solve.threads = 2;
    const Snapshots snapshots = solve_static_loads(t->mesh, t->scene, t->training, solve).value();
    ReductionOptions reduction;
    reduction.source = ReducedBasisSource::pod;
    reduction.basis_size = 24;
    reduction.max_cubature_samples = 64;
    const TissueSolverOptions solver = reduction_solver_options(reduction.force_kind);
    t->basis = make_pod_basis(t->mesh, t->scene, solver, reduction, snapshots.displacements_m, snapshots.count).value();
    EXPECT_TRUE(
        add_force_reduction(t->mesh, t->scene, solver, reduction, snapshots.displacements_m, snapshots.count, t->basis)
            .ok());
    const auto held_out = make_training_loads(t->mesh, t->scene, options, LoadSet::held_out);
    t->calibration = one_side(t->mesh, held_out, t->split_x, true);
    for (const TrainingLoad& load : one_side(t->mesh, held_out, t->split_x, false))
      if (load.name.starts_with("push")) t->untrained_side.push_back(load);
    for (const TrainingLoad& load : t->calibration)
      if (!load.point_forces.empty()) t->trained_side.push_back(load);
    t->calibration_full_m = full_order_solutions(*t, t->calibration);
    auto report = calibrate_error_estimate(t->mesh, t->scene, t->calibration, t->calibration_full_m, t->basis);
    EXPECT_TRUE(report.ok()) << report.error().describe();
    if (report.ok()) t->report = std::move(report).value();
    return t;
  }();
  return instance.get();
}

/// The quasi-static settings of the calibration's reduced solves, and the full order's.
ReducedSolverOptions reduced_options() {
  ReducedSolverOptions o;
  o.integrator = ReducedIntegrator::quasi_static;
  o.step_s = StaticSolveOptions::default_solver().step_s;
  o.newton_iterations = 2;
  o.frozen_tangent = false;
  o.rayleigh_mass_per_s = ReducedStaticOptions{}.relaxation_per_s;
  return o;
}

TEST(ErrorEstimate, CalibratedOnTheTrainedSidesHeldOutLoads) {
  const Trained* t = trained();
  NAV_REQUIRE_SHARED_DATA(testing::shared_data_path("liver/liverFine.vtu"));
  const ReducedErrorCalibration& c = t->basis.error_calibration;
  for (const HeldOutEstimate& load : t->report.loads)
    std::printf("  held out %-24s true %.3f mm, estimated %.3f mm\n", load.load.c_str(), 1e3 * load.true_error_m,
                1e3 * load.estimated_error_m);
  std::printf(
      "error estimate on %d held-out loads with point forces: gain %.3f, correlation %.3f, true / estimated %.2f to "
      "%.2f\n",
      c.held_out_loads, c.gain, c.correlation, c.lowest_ratio, c.highest_ratio);
  EXPECT_GE(c.held_out_loads, 5);
  EXPECT_GT(c.correlation, 0.6);
  EXPECT_GT(c.lowest_ratio, 0.25);  // the estimate is within a factor of 4 of the truth either way
  EXPECT_LT(c.highest_ratio, 4.0);
  // The training loads with point forces (not used by the calibration): the estimate follows
  // their true error too, within the same band or near it.
  std::vector<TrainingLoad> loaded;
  for (const TrainingLoad& load : t->training)
    if (!load.point_forces.empty()) loaded.push_back(load);
  const auto full = full_order_solutions(*t, loaded);
  std::vector<double> truth, estimate;
  int false_alarms = 0;
  for (std::size_t k = 0; k < loaded.size(); ++k) {
    ReducedStepReport last;
    const auto u = solve_reduced_static(t->mesh, t->scene, t->basis, loaded[k], {}, &last);
    ASSERT_TRUE(u.ok()) << u.error().describe();
    truth.push_back(displacement_error(u.value(), full[k], -1).max_m);
    estimate.push_back(last.estimated_error_m);
    false_alarms += last.error_over_bound && truth.back() < ReducedSolverOptions{}.error_bound_m;
    EXPECT_GT(truth.back() / estimate.back(), 0.15) << loaded[k].name;
    EXPECT_LT(truth.back() / estimate.back(), 4.0) << loaded[k].name;
  }
  const double training_correlation = pearson_correlation(truth, estimate);
  std::printf(
      "on the %zu training loads with point forces: correlation %.3f, %d above the 2 mm bound with a smaller error\n",
      truth.size(), training_correlation, false_alarms);
  EXPECT_GT(training_correlation, 0.4);
}

TEST(ErrorEstimate, TheMissingComplianceIsThePatchsFullOrderResponseLessTheBasissOnAnyThreads) {
  const Trained* t = trained();
  NAV_REQUIRE_SHARED_DATA(testing::shared_data_path("liver/liverFine.vtu"));
  const std::vector<double>& one_thread = t->basis.error_calibration.missing_compliance_m_per_n;
  ReducedBasis shared = t->basis;
  ErrorCalibrationOptions three;
  three.threads = 3;
  ASSERT_TRUE(calibrate_error_estimate(t->mesh, t->scene, t->calibration, t->calibration_full_m, shared, three).ok());
  EXPECT_EQ(shared.error_calibration.missing_compliance_m_per_n, one_thread);  // bit for bit

  // The reference, every 25th free node: the patch's load solved with the rest factor (forward
  // and back), its response averaged over the patch, less the basis's static compliance there.
  const auto system =
      detail::make_full_system(t->mesh, t->scene, reduction_solver_options(t->basis.force_kind)).value();
  const std::vector<std::int32_t>& free_nodes = system.model.tables().free_nodes;
  const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> factor(system.stiffness);
  const Eigen::Index r = t->basis.basis_size;
  Eigen::MatrixXd u(system.stiffness.rows(), r);
  for (std::size_t i = 0; i < free_nodes.size(); ++i)
    for (Eigen::Index c = 0; c < r; ++c)
      for (int d = 0; d < 3; ++d)
        u(3 * static_cast<Eigen::Index>(i) + d, c) =
            t->basis.basis[static_cast<std::size_t>(c) * 3 * t->mesh.nodes_m.size() + 3 * free_nodes[i] + d];
  const Eigen::MatrixXd reduced_flexibility = (u.transpose() * system.stiffness * u).inverse();
  const double radius_m = ErrorCalibrationOptions{}.patch_radius_m;
  double worst = 0.0;
  for (std::size_t i = 0; i < free_nodes.size(); i += 25) {
    const Point3& centre = t->mesh.nodes_m[static_cast<std::size_t>(free_nodes[i])];
    Eigen::MatrixXd patch_load = Eigen::MatrixXd::Zero(system.stiffness.rows(), 3);
    for (std::size_t j = 0; j < free_nodes.size(); ++j) {
      const Point3& p = t->mesh.nodes_m[static_cast<std::size_t>(free_nodes[j])];
      const double d2 = (p[0] - centre[0]) * (p[0] - centre[0]) + (p[1] - centre[1]) * (p[1] - centre[1]) +
                        (p[2] - centre[2]) * (p[2] - centre[2]);
      if (d2 <= radius_m * radius_m) patch_load.middleRows<3>(3 * static_cast<Eigen::Index>(j)).setIdentity();
    }
    patch_load /= patch_load.col(0).sum();
    const Eigen::MatrixXd response = factor.solve(patch_load);
    const Eigen::Matrix3d full = patch_load.transpose() * response;
    const Eigen::Matrix3d reduced = (patch_load.transpose() * u) * reduced_flexibility * (u.transpose() * patch_load);
    const Eigen::Matrix3d expected = full - reduced;
    const double* packed = one_thread.data() + 6 * static_cast<std::size_t>(free_nodes[i]);
    const Eigen::Matrix3d got = (Eigen::Matrix3d() << packed[0], packed[1], packed[2], packed[1], packed[3], packed[4],
                                 packed[2], packed[4], packed[5])
                                    .finished();
    worst = std::max(worst, (got - expected).norm() / full.norm());
  }
  std::printf("missing patch compliance against forward and back solves: worst relative difference %.2e\n", worst);
  EXPECT_LT(worst, 1e-9);
}

TEST(ErrorEstimate, AnUntrainedPushInsideTheEnvelopeFiresItAndTheLadderEscalatesToAQuarterOfTheError) {
  const Trained* t = trained();
  NAV_REQUIRE_SHARED_DATA(testing::shared_data_path("liver/liverFine.vtu"));
  ASSERT_FALSE(t->untrained_side.empty());
  // The push on the untrained side with the largest error.
  const auto full = full_order_solutions(*t, t->untrained_side);
  std::size_t worst = 0;
  double error_before_m = 0.0;
  ReducedStepReport report;
  for (std::size_t k = 0; k < t->untrained_side.size(); ++k) {
    ReducedStepReport last;
    const auto u = solve_reduced_static(t->mesh, t->scene, t->basis, t->untrained_side[k], {}, &last);
    ASSERT_TRUE(u.ok()) << u.error().describe();
    const double e = displacement_error(u.value(), full[k], -1).max_m;
    if (e > error_before_m) worst = k, error_before_m = e, report = last;
  }
  const TrainingLoad& push = t->untrained_side[worst];
  const double bound_m = ReducedSolverOptions{}.error_bound_m;
  std::printf(
      "untrained %s at x = %.1f mm (trained side below %.1f mm): true error %.3f mm, estimated %.3f mm (bound %.3f "
      "mm), "
      "envelope ratio %.2f\n",
      push.name.c_str(), 1e3 * load_x(t->mesh, push), 1e3 * t->split_x, 1e3 * error_before_m,
      1e3 * report.estimated_error_m, 1e3 * bound_m, report.envelope_ratio);
  EXPECT_LE(report.envelope_ratio, ReducedSolverOptions{}.envelope_factor);  // |q| alone sees nothing
  EXPECT_FALSE(report.out_of_envelope);
  EXPECT_TRUE(report.error_over_bound);
  EXPECT_GT(report.estimated_error_m, bound_m);

  // A ladder of the reduced liver topped by the full order, ramped to the push as the
  // calibration's solves are.
  const std::vector<ReducedRungSpec> rungs{{t->basis, reduced_options()}};
  const TissueScene scene = scene_for_load(t->scene, push);
  auto ladder = make_reduced_ladder_model(t->mesh, scene, StaticSolveOptions::default_solver(), rungs, true, {});
  ASSERT_TRUE(ladder.ok()) << ladder.error().describe();
  auto data = make_reduced_ladder_data(ladder.value()).value();
  const ReducedStaticOptions ramp;
  int first_escalation = -1;
  for (int s = 1; s <= ramp.ramp_steps + 200; ++s) {
    step(ladder.value(), data, push.inputs(std::min(1.0, static_cast<double>(s) / ramp.ramp_steps)));
    if (first_escalation < 0 && data.report.escalated) first_escalation = s;
  }
  std::vector<double> u(3 * t->mesh.nodes_m.size());
  reconstruct_all_displacements_m(ladder.value(), data, u);
  const double error_after_m = displacement_error(u, full[worst], -1).max_m;
  std::printf("the ladder escalated at step %d of the ramp; error after %.4f mm, before %.3f mm (%.1f %%)\n",
              first_escalation, 1e3 * error_after_m, 1e3 * error_before_m, 100.0 * error_after_m / error_before_m);
  EXPECT_GT(first_escalation, 0);
  EXPECT_EQ(data.active_rung, 1);
  EXPECT_TRUE(data.health.has(HealthFlag::reduced_error_over_bound));
  EXPECT_TRUE(data.health.has(HealthFlag::reduced_escalated));
  EXPECT_LT(error_after_m, 0.25 * error_before_m);
}

TEST(ErrorEstimate, TheStepWithTheEstimateNeverAllocates) {
  const Trained* t = trained();
  NAV_REQUIRE_SHARED_DATA(testing::shared_data_path("liver/liverFine.vtu"));
  const ReducedModel model =
      make_reduced_model(t->mesh, t->scene, reduction_solver_options(t->basis.force_kind), t->basis, {}).value();
  ReducedData data = make_reduced_data(model).value();
  std::vector<PointForce> forces;
  const auto count = static_cast<std::int32_t>(t->scene.max_point_forces);
  for (std::int32_t n = 0; n < count; ++n) forces.push_back({n % 5 == 0 ? 7 : 40 + n, {0.0, 0.01, -0.005}});
  TissueInputs inputs;
  inputs.point_forces = forces;
  testing::AllocationGuard guard;
  for (int s = 0; s < 50; ++s) step(model, data, inputs);
  EXPECT_EQ(guard.allocations(), 0u);
  EXPECT_FALSE(data.health.has(HealthFlag::bad_sample));
  EXPECT_GT(data.report.estimated_error_m, 0.0);
}

}  // namespace
}  // namespace nav
