// The reduced-coordinate Kalman filter: with a constant truth and no process noise it equals
// the batch information-form (weighted least squares with prior) solution; with process
// noise it equals a textbook dense Kalman filter; on a beam whose truth is the full-order
// corotational model with a softer material than the reduced model's, it brings the target
// error well below the open-loop reduced model's, with consistent covariances (NEES); it
// gates outliers; predict/update never allocate and repeat bitwise.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <random>
#include <vector>

#include "nav/fusion/reduced_kalman.hpp"
#include "nav/reduced/reduced_model.hpp"
#include "nav/reduced/reduction.hpp"
#include "reduced/reduced_test_support.hpp"
#include "support/allocation_guard.hpp"

namespace nav {
namespace {

using testing::BeamScene;
using testing::bits_hash;

/// The lowest `r` vibration modes of `beam` (linear force), without a training envelope.
ReducedBasis modes(const BeamScene& beam, int r, ReducedForceKind kind) {
  ReductionOptions options;
  options.source = ReducedBasisSource::linear_modes;
  options.force_kind = kind;
  options.basis_size = r;
  options.max_cubature_samples = 32;
  auto basis = make_modal_basis(beam.mesh, beam.scene, TissueSolverOptions{}, options);
  EXPECT_TRUE(basis.ok()) << basis.error().describe();
  return basis.value();
}

/// The observation matrix (3 x r) and rest position of a point, straight from the basis.
struct PointRows {
  Eigen::MatrixXd h;
  Eigen::Vector3d rest;
};
PointRows point_rows(const BeamScene& beam, const ReducedBasis& basis, const ObservedPoint& p) {
  const Eigen::MatrixXd u = testing::basis_matrix(basis);
  PointRows out{Eigen::MatrixXd::Zero(3, basis.basis_size), Eigen::Vector3d::Zero()};
  for (int a = 0; a < 4; ++a) {
    const auto node = static_cast<Eigen::Index>(p.nodes[static_cast<std::size_t>(a)]);
    out.h += p.weights[static_cast<std::size_t>(a)] * u.middleRows(3 * node, 3);
    for (int c = 0; c < 3; ++c)
      out.rest[c] += p.weights[static_cast<std::size_t>(a)] *
                     beam.mesh.nodes_m[static_cast<std::size_t>(node)][static_cast<std::size_t>(c)];
  }
  return out;
}

Eigen::Map<const Eigen::MatrixXd> covariance_of(const ReducedKalmanData& data, int r) {
  return Eigen::Map<const Eigen::MatrixXd>(data.covariance.data(), r, r);
}

void expect_symmetric_positive_definite(const ReducedKalmanData& data, int r) {
  const auto p = covariance_of(data, r);
  EXPECT_EQ((p - p.transpose()).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ(Eigen::LLT<Eigen::MatrixXd>(p).info(), Eigen::Success);
}

/// A small beam, its 6 lowest modes, a reduced model held in a fixed state q, and two
/// observed points (a node and a point inside a tetrahedron).
struct StaticSetup {
  BeamScene beam{{0.04, 0.01, 0.01}, 0.005};
  ReducedBasis basis = modes(beam, 6, ReducedForceKind::linear);
  ReducedModel reduced = make_reduced_model(beam.mesh, beam.scene, TissueSolverOptions{}, basis, {}).value();
  ReducedData reduced_data = make_reduced_data(reduced).value();
  std::vector<ObservedPoint> points;
  StaticSetup() {
    const auto tet = beam.mesh.tets[beam.mesh.tets.size() / 2];
    points = {observed_node(static_cast<std::int32_t>(beam.mesh.nodes_m.size() - 1)),
              ObservedPoint{{tet[0], tet[1], tet[2], tet[3]}, {0.1, 0.2, 0.3, 0.4}}};
    for (int i = 0; i < 6; ++i)
      reduced_data.q[static_cast<std::size_t>(i)] = 1e-4 * (i + 1) * (i % 2 == 0 ? 1.0 : -1.0);
  }
};

TEST(ReducedKalman, ConstantTruthWithoutProcessNoiseEqualsBatchInformationForm) {
  StaticSetup s;
  const int r = 6;
  ReducedKalmanOptions options;
  options.correction_std.assign(r, 5e-4);
  options.observation_std_m = 0.001;
  options.gate_chi_square = 1e9;  // the reference has no gate
  const auto model = make_reduced_kalman_model(s.beam.mesh, s.basis, s.reduced, s.points, options);
  ASSERT_TRUE(model.ok()) << model.error().describe();
  auto data = make_reduced_kalman_data(model.value()).value();

  Eigen::VectorXd q_model(r), dq_true(r);
  for (int i = 0; i < r; ++i) q_model[i] = s.reduced_data.q[static_cast<std::size_t>(i)];
  for (int i = 0; i < r; ++i) dq_true[i] = 3e-4 * std::cos(1.0 + i);
  const double variance = options.observation_std_m * options.observation_std_m;
  Eigen::MatrixXd information = Eigen::MatrixXd::Identity(r, r) / (5e-4 * 5e-4);
  Eigen::VectorXd information_vector = Eigen::VectorXd::Zero(r);
  std::mt19937_64 rng(7);
  std::normal_distribution<double> noise(0.0, options.observation_std_m);
  for (int frame = 0; frame < 40; ++frame) {
    predict(model.value(), data, s.reduced_data);
    for (int k = 0; k < 2; ++k) {
      const PointRows rows = point_rows(s.beam, s.basis, s.points[static_cast<std::size_t>(k)]);
      Eigen::Vector3d z = rows.rest + rows.h * (q_model + dq_true);
      for (int c = 0; c < 3; ++c) z[c] += noise(rng);
      ASSERT_TRUE(update(model.value(), data, k, {z[0], z[1], z[2]}, frame));
      information += rows.h.transpose() * rows.h / variance;
      const Eigen::Vector3d residual = z - rows.rest - rows.h * q_model;
      const Eigen::VectorXd share = rows.h.transpose() * residual;
      information_vector += share / variance;
      expect_symmetric_positive_definite(data, r);
    }
  }
  const Eigen::MatrixXd batch_covariance = information.inverse();
  const Eigen::VectorXd batch_dq = batch_covariance * information_vector;
  const Eigen::Map<const Eigen::VectorXd> dq(data.correction.data(), r);
  EXPECT_LT((dq - batch_dq).norm(), 1e-9 * batch_dq.norm());
  EXPECT_LT((covariance_of(data, r) - batch_covariance).cwiseAbs().maxCoeff(),
            1e-9 * batch_covariance.cwiseAbs().maxCoeff());
  // The estimate converges to the truth within its own covariance.
  const Eigen::VectorXd error = dq - dq_true;
  EXPECT_LT(error.dot(information * error), 30.0);  // chi-square, 6 dof: p = 4e-5
  EXPECT_TRUE(data.health.healthy());
}

TEST(ReducedKalman, GaussMarkovCorrectionEqualsTextbookDenseFilter) {
  StaticSetup s;
  const int r = 6;
  ReducedKalmanOptions options;
  for (int i = 0; i < r; ++i) options.correction_std.push_back(2e-4 * (1.0 + 0.3 * i));
  options.correlation_time_s = 0.05;  // 20 model steps of 1 ms
  options.gate_chi_square = 1e9;
  const auto model = make_reduced_kalman_model(s.beam.mesh, s.basis, s.reduced, s.points, options).value();
  auto data = make_reduced_kalman_data(model).value();
  // The reference: x = a x + w, Q = (1 - a^2) S; z = x0 + H (q + x); standard gain and Joseph form.
  const double a = std::exp(-s.reduced.options().step_s / options.correlation_time_s);
  Eigen::VectorXd stationary(r);
  for (int i = 0; i < r; ++i)
    stationary[i] =
        options.correction_std[static_cast<std::size_t>(i)] * options.correction_std[static_cast<std::size_t>(i)];
  Eigen::MatrixXd p = stationary.asDiagonal();
  Eigen::VectorXd x = Eigen::VectorXd::Zero(r), q_model(r);
  for (int i = 0; i < r; ++i) q_model[i] = s.reduced_data.q[static_cast<std::size_t>(i)];
  const Eigen::Matrix3d noise_covariance = Eigen::Matrix3d::Identity() * 1e-6;
  std::mt19937_64 rng(11);
  std::normal_distribution<double> noise(0.0, 0.002);
  for (int step = 0; step < 60; ++step) {
    predict(model, data, s.reduced_data);
    x *= a;
    p = a * a * p + Eigen::MatrixXd((1.0 - a * a) * stationary.asDiagonal());
    if (step % 3 != 0) continue;
    const int k = (step / 3) % 2;
    const PointRows rows = point_rows(s.beam, s.basis, s.points[static_cast<std::size_t>(k)]);
    Eigen::Vector3d z = rows.rest + rows.h * q_model;
    for (int c = 0; c < 3; ++c) z[c] += noise(rng);
    ASSERT_TRUE(update(model, data, k, {z[0], z[1], z[2]}, step));
    const Eigen::Matrix3d innovation_covariance = rows.h * p * rows.h.transpose() + noise_covariance;
    const Eigen::MatrixXd gain = p * rows.h.transpose() * innovation_covariance.inverse();
    x += gain * (z - rows.rest - rows.h * (q_model + x));
    const Eigen::MatrixXd i_kh = Eigen::MatrixXd::Identity(r, r) - gain * rows.h;
    p = i_kh * p * i_kh.transpose() + gain * noise_covariance * gain.transpose();
    const Eigen::Map<const Eigen::VectorXd> dq(data.correction.data(), r);
    ASSERT_LT((dq - x).norm(), 1e-9 * x.norm()) << step;
    ASSERT_LT((covariance_of(data, r) - p).cwiseAbs().maxCoeff(), 1e-9 * p.cwiseAbs().maxCoeff()) << step;
    expect_symmetric_positive_definite(data, r);
  }
  // The point estimate and its covariance are H (q + dq) + x0 and H P H^T.
  const PointRows rows = point_rows(s.beam, s.basis, s.points[1]);
  const PointEstimate estimate = estimate_point(model, data, 1);
  const Eigen::Vector3d expected = rows.rest + rows.h * (q_model + x);
  const Eigen::Matrix3d expected_covariance = rows.h * p * rows.h.transpose();
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(estimate.position_m[static_cast<std::size_t>(c)], expected[c], 1e-12);
    for (int e = 0; e < 3; ++e)
      EXPECT_NEAR(estimate.covariance_m2[static_cast<std::size_t>(3 * c + e)], expected_covariance(c, e),
                  1e-9 * expected_covariance.norm());
  }
}

TEST(ReducedKalman, GatesOutliersAndRefusesBadSamplesWithTheStateUntouched) {
  StaticSetup s;
  ReducedKalmanOptions options;
  options.correction_std.assign(6, 2e-5);  // about 0.3 mm at the free end
  const auto model = make_reduced_kalman_model(s.beam.mesh, s.basis, s.reduced, s.points, options).value();
  auto data = make_reduced_kalman_data(model).value();
  predict(model, data, s.reduced_data);
  const PointEstimate prior = estimate_point(model, data, 0);
  std::uint64_t before = bits_hash({data.correction, data.covariance});
  const auto expect_refused = [&](int point, const Point3& z, TimeNs t) {
    data.health.clear_all();
    EXPECT_FALSE(update(model, data, point, z, t));
    EXPECT_TRUE(data.health.has(HealthFlag::bad_sample));
    EXPECT_EQ(bits_hash({data.correction, data.covariance}), before);
  };
  const Point3 p = prior.position_m;
  expect_refused(0, {p[0], p[1], p[2] + 0.05}, 10);  // 5 cm off: far outside the gate
  EXPECT_GT(data.last_mahalanobis_squared, model.gate_chi_square);
  expect_refused(0, {p[0], std::numeric_limits<double>::quiet_NaN(), p[2]}, 10);
  expect_refused(2, p, 10);  // no such point
  expect_refused(-1, p, 10);
  EXPECT_EQ(data.rejected_updates, 4);
  data.health.clear_all();
  EXPECT_TRUE(update(model, data, 0, {p[0], p[1], p[2] + 0.001}, 10));  // 1 mm off: accepted
  EXPECT_TRUE(data.health.healthy());
  EXPECT_LT(data.last_mahalanobis_squared, model.gate_chi_square);
  EXPECT_NE(bits_hash({data.correction, data.covariance}), before);
  before = bits_hash({data.correction, data.covariance});
  expect_refused(0, p, 9);  // the clock went backwards
  EXPECT_EQ(data.accepted_updates, 1);
  // Init-time errors name their field.
  ReducedKalmanOptions wrong = options;
  wrong.correction_std.pop_back();
  EXPECT_EQ(make_reduced_kalman_model(s.beam.mesh, s.basis, s.reduced, s.points, wrong).error().field,
            "correction_std");
  std::vector<ObservedPoint> outside = s.points;
  outside[1].weights[0] = 0.5;
  EXPECT_EQ(make_reduced_kalman_model(s.beam.mesh, s.basis, s.reduced, outside, options).error().field, "points[1]");
}

// --- The real use: a softer truth than the reduced model, seen through 1 mm noise. ---

constexpr double kModelYoungsPa = 20.0e3, kTruthYoungsPa = 14.0e3;
constexpr int kSteps = 250, kObserveEvery = 2;  // 50 Hz model steps, 25 Hz ultrasound
constexpr double kStepS = 0.02;

/// A 4 x 2 x 2 cm beam held at x = 0 under gravity (-z), its free end pulled by a breathing-like
/// force; the target is the node nearest (3 cm, 1 cm, 1 cm).
struct BeamCase {
  BeamScene model_beam{{0.04, 0.02, 0.02}, 0.005};
  std::int32_t target = 0, tip = 0;
  PointForce force{};
  BeamCase() {
    model_beam.scene.default_material.youngs_modulus_pa = kModelYoungsPa;
    double best = 1e9;
    for (std::size_t n = 0; n < model_beam.mesh.nodes_m.size(); ++n) {
      const auto& x = model_beam.mesh.nodes_m[n];
      const double d = std::hypot(x[0] - 0.03, x[1] - 0.01, x[2] - 0.01);
      if (d < best) best = d, target = static_cast<std::int32_t>(n);
      if (x[0] > 0.04 - 1e-9 && std::abs(x[1] - 0.01) < 1e-9 && std::abs(x[2] - 0.02) < 1e-9)
        tip = static_cast<std::int32_t>(n);
    }
  }
  TissueInputs inputs(int step) {
    force = {tip,
             {0.0, 0.004 * std::sin(2.0 * std::numbers::pi * step * kStepS / 2.0),
              0.006 * std::sin(2.0 * std::numbers::pi * step * kStepS / 3.0)}};
    TissueInputs in;
    in.load_scale = std::min(1.0, 0.1 * (step + 1));
    in.point_forces = std::span<const PointForce>(&force, 1);
    return in;
  }
};

TissueSolverOptions quasi_static_corotational() {
  TissueSolverOptions o;
  o.integrator = Integrator::quasi_static;
  o.step_s = kStepS;
  o.cg_iterations = 3;
  return o;
}

/// The truth: the full-order corotational model with the softer material, target positions per step.
std::vector<Point3> truth_trajectory(BeamCase& c) {
  TissueScene scene = c.model_beam.scene;
  scene.default_material.youngs_modulus_pa = kTruthYoungsPa;
  const TetFemModel full = make_tet_fem_model(c.model_beam.mesh, scene, quasi_static_corotational()).value();
  auto data = make_tet_fem_data(full).value();
  std::vector<Point3> out;
  for (int i = 0; i < kSteps; ++i) {
    step(full, data, c.inputs(i));
    const auto t = static_cast<std::size_t>(c.target);
    out.push_back({data.positions_m[3 * t], data.positions_m[3 * t + 1], data.positions_m[3 * t + 2]});
  }
  return out;
}

/// The reduced model: 10 modes, corotational cubature trained on the model material's own
/// gravity-and-tip-force ramp (which gives the training envelope the correction is scaled by).
struct ReducedCase {
  BeamCase beam;
  ReducedBasis basis;
  ReducedModel reduced{nullptr};
  std::vector<Point3> truth;
  std::vector<Point3> observations;
  ReducedCase() {
    const TissueSolverOptions solver = quasi_static_corotational();
    ReductionOptions options;
    options.source = ReducedBasisSource::linear_modes;
    options.force_kind = ReducedForceKind::corotational_cubature;
    options.basis_size = 10;
    options.max_cubature_samples = 32;
    basis = make_modal_basis(beam.model_beam.mesh, beam.model_beam.scene, solver, options).value();
    const TetFemModel full = make_tet_fem_model(beam.model_beam.mesh, beam.model_beam.scene, solver).value();
    const auto snapshots = testing::full_order_snapshots(full, 60, 6, [&](int i) { return beam.inputs(i); });
    EXPECT_TRUE(
        add_force_reduction(beam.model_beam.mesh, beam.model_beam.scene, solver, options, snapshots, 10, basis).ok());
    ReducedSolverOptions reduced_options;
    reduced_options.integrator = ReducedIntegrator::quasi_static;
    reduced_options.step_s = kStepS;
    reduced_options.newton_iterations = 2;
    reduced_options.frozen_tangent = false;
    reduced = make_reduced_model(beam.model_beam.mesh, beam.model_beam.scene, solver, basis, reduced_options).value();
    truth = truth_trajectory(beam);
    std::mt19937_64 rng(2024);
    std::normal_distribution<double> noise(0.0, 0.001);
    for (const Point3& p : truth) observations.push_back({p[0] + noise(rng), p[1] + noise(rng), p[2] + noise(rng)});
  }
};

const ReducedCase& reduced_case() {
  static const ReducedCase c;
  return c;
}

ReducedKalmanOptions beam_options(const ReducedBasis& basis) {
  ReducedKalmanOptions o;
  o.correction_std = correction_std_from_training(basis, 1.0);  // the error may be as large as the envelope
  o.correlation_time_s = 2.0;                                   // the loads change over seconds
  o.observation_std_m = 0.001;
  return o;
}

/// One closed-loop run: target errors (open loop and filtered) and NEES per step, the
/// allocations of the loop and a hash of the filter's trajectory.
struct FilterRun {
  std::vector<double> open_loop_m, filtered_m, nees;
  std::size_t allocations = 1;
  std::uint64_t hash = 0;
};

FilterRun run_filter() {
  const ReducedCase& c = reduced_case();
  BeamCase beam = c.beam;
  const std::vector<ObservedPoint> points{observed_node(beam.target)};
  const auto model = make_reduced_kalman_model(beam.model_beam.mesh, c.basis, c.reduced, points, beam_options(c.basis));
  EXPECT_TRUE(model.ok()) << model.error().describe();
  auto data = make_reduced_kalman_data(model.value()).value();
  auto reduced = make_reduced_data(c.reduced).value();
  std::vector<PointEstimate> estimates(kSteps);
  std::vector<Point3> open_loop(kSteps);
  std::vector<double> trace(kSteps * 3);
  FilterRun run;
  {
    testing::AllocationGuard guard;
    for (int i = 0; i < kSteps; ++i) {
      const auto si = static_cast<std::size_t>(i);
      step(c.reduced, reduced, beam.inputs(i));
      predict(model.value(), data, reduced);
      for (int k = 0; k < 3; ++k)
        open_loop[si][static_cast<std::size_t>(k)] = data.model_points_m[static_cast<std::size_t>(k)];
      if (i % kObserveEvery == 0)
        update(model.value(), data, 0, c.observations[si], static_cast<TimeNs>(i) * 20'000'000);
      estimates[si] = estimate_point(model.value(), data, 0);
      for (int k = 0; k < 3; ++k)
        trace[3 * si + static_cast<std::size_t>(k)] = estimates[si].position_m[static_cast<std::size_t>(k)];
    }
    run.allocations = guard.allocations();
  }
  run.hash = bits_hash({trace, data.covariance});
  for (std::size_t i = 0; i < estimates.size(); ++i) {
    Eigen::Vector3d e, o;
    Eigen::Matrix3d cov;
    for (int k = 0; k < 3; ++k) {
      e[k] = c.truth[i][static_cast<std::size_t>(k)] - estimates[i].position_m[static_cast<std::size_t>(k)];
      o[k] = c.truth[i][static_cast<std::size_t>(k)] - open_loop[i][static_cast<std::size_t>(k)];
      for (int l = 0; l < 3; ++l) cov(k, l) = estimates[i].covariance_m2[static_cast<std::size_t>(3 * k + l)];
    }
    run.filtered_m.push_back(e.norm());
    run.open_loop_m.push_back(o.norm());
    run.nees.push_back(e.dot(cov.llt().solve(e)));
  }
  EXPECT_TRUE(data.health.healthy()) << data.health.bits();
  std::printf("accepted %lld, rejected %lld\n", static_cast<long long>(data.accepted_updates),
              static_cast<long long>(data.rejected_updates));
  return run;
}

double rms(const std::vector<double>& v, std::size_t from) {
  double sum = 0.0;
  for (std::size_t i = from; i < v.size(); ++i) sum += v[i] * v[i];
  return std::sqrt(sum / static_cast<double>(v.size() - from));
}

TEST(ReducedKalman, SofterFullOrderTruthSeenThroughOneMillimetreNoise) {
  const FilterRun run = run_filter();
  const std::size_t settled = 26;  // after the load ramp and half a second of frames
  const double open_rms = rms(run.open_loop_m, settled), filtered_rms = rms(run.filtered_m, settled);
  double open_max = 0.0;
  for (std::size_t i = 0; i < run.open_loop_m.size(); ++i) open_max = std::max(open_max, run.open_loop_m[i]);
  // NEES of the posterior at the update times: its mean over n independent samples is
  // chi-square with 3 n degrees of freedom over n; the 99 % band by Wilson-Hilferty.
  double nees_sum = 0.0;
  int samples = 0;
  for (std::size_t i = settled; i < run.nees.size(); i += kObserveEvery, ++samples) nees_sum += run.nees[i];
  const double nees_mean = nees_sum / samples, dof = 3.0 * samples;
  const auto quantile = [&](double z) {
    return dof * std::pow(1.0 - 2.0 / (9.0 * dof) + z * std::sqrt(2.0 / (9.0 * dof)), 3.0) / samples;
  };
  std::printf(
      "target error RMS: open loop %.3f mm, filtered %.3f mm (largest open-loop %.3f mm); mean NEES %.2f over %d "
      "updates (99 %% band %.2f to %.2f)\n",
      1e3 * open_rms, 1e3 * filtered_rms, 1e3 * open_max, nees_mean, samples, quantile(-2.576), quantile(2.576));
  EXPECT_LT(filtered_rms, 0.5 * open_rms);
  EXPECT_LT(filtered_rms, 0.8e-3);
  EXPECT_GT(nees_mean, quantile(-2.576));
  EXPECT_LT(nees_mean, quantile(2.576));
}

TEST(ReducedKalman, PredictAndUpdateNeverAllocateAndRepeatBitwise) {
  const FilterRun first = run_filter();
  const FilterRun second = run_filter();
  EXPECT_EQ(first.allocations, 0u);
  EXPECT_EQ(second.allocations, 0u);
  EXPECT_EQ(first.hash, second.hash);
}

}  // namespace
}  // namespace nav
