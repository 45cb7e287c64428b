// The flexible needle as corotational beams: cantilever against Euler-Bernoulli and
// Timoshenko, an end moment rolling it into a circle, rigid motions without force, the
// O(n) block solver against a dense one, allocation-free and bitwise repeatable steps; the
// element response from its shared blocks and sparse force terms is the full one's, bit for bit.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <numbers>

#include "nav/needle/needle_step.hpp"
#include "nav/needle/rotation_vector.hpp"
#include "needle_test_support.hpp"
#include "support/allocation_guard.hpp"

namespace nav {
namespace {

NeedleInputs at_origin() { return NeedleInputs{}; }

TEST(NeedleBeam, CantileverTipDeflectionMatchesEulerBernoulliWithinOnePercent) {
  const NeedleModel model = make_needle_model(testing::quasi_static_needle()).value();
  NeedleData data = make_needle_data(model, {}).value();
  const double ei = model.parameters.youngs_modulus_pa * model.section.second_moment_m4, l = model.parameters.length_m;
  const double load_n = 1e-4 * 3.0 * ei / (l * l);  // deflection 1e-4 L: geometrically linear
  NeedleInputs inputs = at_origin();
  inputs.tip_force_n = {0.0, 0.0, -load_n};
  step(model, data, inputs);
  const double expected_m = load_n * l * l * l / (3.0 * ei);
  const double error = std::abs(-needle_tip_m(data).z() - expected_m) / expected_m;
  RecordProperty("relative_error", std::to_string(error));
  std::printf("Euler-Bernoulli cantilever, 20 elements: relative tip deflection error %.2e\n", error);
  EXPECT_LT(error, 0.01);
}

TEST(NeedleBeam, CantileverTipDeflectionIncludesTimoshenkoShear) {
  NeedleParameters p = testing::quasi_static_needle(BeamTheory::timoshenko);
  p.length_m = 0.01;  // short and thick, so that shear counts (about 1 % of the bending term)
  p.outer_diameter_m = 2e-3;
  p.inner_diameter_m = 1e-3;
  const NeedleModel model = make_needle_model(p).value();
  NeedleData data = make_needle_data(model, {}).value();
  const double ei = p.youngs_modulus_pa * model.section.second_moment_m4, l = p.length_m;
  const double load_n = 1e-4 * 3.0 * ei / (l * l);
  NeedleInputs inputs = at_origin();
  inputs.tip_force_n = {0.0, load_n, 0.0};
  step(model, data, inputs);
  const double bending_m = load_n * l * l * l / (3.0 * ei);
  const double shear_m =
      load_n * l / (model.section.shear_coefficient * model.section.shear_modulus_pa * model.section.area_m2);
  const double error = std::abs(needle_tip_m(data).y() - (bending_m + shear_m)) / (bending_m + shear_m);
  std::printf("Timoshenko cantilever, 20 elements: shear share %.2f %%, relative error %.2e\n",
              100.0 * shear_m / (bending_m + shear_m), error);
  EXPECT_LT(error, 0.01);
  EXPECT_GT(shear_m / bending_m, 0.005);  // the test would see a missing shear term
}

TEST(NeedleBeam, EndMomentTwoPiEIOverLRollsTheNeedleIntoACircle) {
  NeedleParameters p = testing::quasi_static_needle();
  p.newton_iterations = 20;
  const NeedleModel model = make_needle_model(p).value();
  NeedleData data = make_needle_data(model, {}).value();
  const double ei = p.youngs_modulus_pa * model.section.second_moment_m4, l = p.length_m;
  const int increments = 40;
  NeedleInputs inputs = at_origin();
  for (int k = 1; k <= increments; ++k) {
    inputs.tip_moment_n_m = {0.0, 0.0, 2.0 * std::numbers::pi * ei / l * k / increments};
    step(model, data, inputs);
  }
  ASSERT_TRUE(data.health.healthy());
  const double radius_m = l / (2.0 * std::numbers::pi);
  const Eigen::Vector3d centre(0.0, radius_m, 0.0);
  double worst_radius = 0.0;
  for (int n = 0; n < model.node_count(); ++n) {
    const Eigen::Vector3d x(data.positions_m[3 * n], data.positions_m[3 * n + 1], data.positions_m[3 * n + 2]);
    worst_radius = std::max(worst_radius, std::abs((x - centre).norm() - radius_m) / radius_m);
  }
  const double tip_gap = needle_tip_m(data).norm() / l;
  std::printf("circle: tip back at the base within %.2e L, radius error %.2e, tip direction x %.6f\n", tip_gap,
              worst_radius, needle_tip_direction(data).x());
  EXPECT_LT(tip_gap, 0.01);
  EXPECT_LT(worst_radius, 0.01);
  EXPECT_GT(needle_tip_direction(data).x(), std::cos(0.01 * 2.0 * std::numbers::pi));
}

TEST(NeedleBeam, RigidMotionOfTheWholeNeedleGivesZeroForce) {
  NeedleParameters p = testing::quasi_static_needle();
  p.newton_iterations = 1;
  p.max_pose_jump_m = 1.0;
  const NeedleModel model = make_needle_model(p).value();
  NeedleData data = make_needle_data(model, {}).value();
  NeedleInputs inputs;
  inputs.base.position_m = {0.03, -0.02, 0.05};
  const Eigen::Quaterniond q = quaternion_from_rotation_vector(Eigen::Vector3d(0.7, -1.1, 0.4));
  inputs.base.rotation_wxyz = {q.w(), q.x(), q.y(), q.z()};
  step(model, data, inputs);
  ASSERT_TRUE(data.health.healthy());
  double worst_force = 0.0;
  for (double f : data.forces) worst_force = std::max(worst_force, std::abs(f));
  EXPECT_LT(worst_force, 1e-9);  // newtons (and N m): rounding only
  const Eigen::Vector3d expected_tip = Eigen::Vector3d(0.03, -0.02, 0.05) + q * Eigen::Vector3d(p.length_m, 0, 0);
  EXPECT_LT((needle_tip_m(data) - expected_tip).norm(), 1e-12);
}

TEST(NeedleBeam, RotationVectorLogarithmMatchesALongDoubleReferenceAtEveryAngle) {
  // Angles from 1e-9 rad to pi - 1e-6 rad, through the small-angle series and past its end
  // (near 0.1 rad), about three axes; the reference is 2 atan2(s, w) / s v in long double.
  double worst = 0.0;
  for (double angle = 1e-9; angle < std::numbers::pi; angle *= 1.07) {
    for (const Eigen::Vector3d& axis :
         {Eigen::Vector3d(1, 0, 0), Eigen::Vector3d(0.6, -0.8, 0), Eigen::Vector3d(Eigen::Vector3d(1, 2, -2) / 3.0)}) {
      const Eigen::Quaterniond q = quaternion_from_rotation_vector(angle * axis);
      const long double s = std::hypot(std::hypot(static_cast<long double>(q.x()), static_cast<long double>(q.y())),
                                       static_cast<long double>(q.z()));
      const long double scale = 2.0L * std::atan2(s, static_cast<long double>(q.w())) / s;
      const Eigen::Vector3d theta = rotation_vector_from_quaternion(q);
      for (int d = 0; d < 3; ++d) {
        const long double reference = scale * static_cast<long double>(q.coeffs()[d]);
        if (reference != 0.0L)
          worst = std::max(worst, static_cast<double>(std::abs((theta[d] - reference) / reference)));
      }
    }
  }
  EXPECT_LT(worst, 1e-15);  // relative, a few roundings
}

TEST(NeedleBeam, SharedTangentBlocksAndSparseForceTermsGiveTheFullResponseBitForBit) {
  for (BeamTheory theory : {BeamTheory::euler_bernoulli, BeamTheory::timoshenko}) {
    NeedleParameters p;
    p.theory = theory;
    const NeedleModel model = make_needle_model(p).value();
    const BeamStiffness& shared = model.local_stiffness;
    int distinct = 0;
    for (int b = 0; b < BeamStiffness::kTangentBlocks; ++b)
      distinct += shared.same_block_as[static_cast<std::size_t>(b)] == b ? 1 : 0;
    EXPECT_EQ(distinct, 6);  // the translation, rotation and coupling blocks of a and b repeat
    // Every block rotated on its own, every moved freedom's term kept (zeros too).
    BeamStiffness full = shared;
    constexpr int kMoved[BeamStiffness::kMovedFreedoms] = {3, 4, 5, 6, 9, 10, 11};
    for (std::size_t i = 0; i < 12; ++i) {
      full.force_term_count[i] = BeamStiffness::kMovedFreedoms;
      for (std::size_t t = 0; t < BeamStiffness::kMovedFreedoms; ++t)
        full.force_terms[i][t] = {kMoved[t], shared.local(static_cast<Eigen::Index>(i), kMoved[t])};
    }
    for (int b = 0; b < BeamStiffness::kTangentBlocks; ++b) full.same_block_as[static_cast<std::size_t>(b)] = b;
    // A bent, stretched and twisted element.
    const double l = model.element_length_m;
    const BeamEnds ends{Eigen::Vector3d(0.001, -0.002, 0.0005),
                        Eigen::Vector3d(0.001 + 1.01 * l, -0.002 + 0.03 * l, 0.0005 - 0.02 * l),
                        Eigen::Quaterniond(Eigen::AngleAxisd(0.02, Eigen::Vector3d(0.3, 0.4, -0.5).normalized())),
                        Eigen::Quaterniond(Eigen::AngleAxisd(0.05, Eigen::Vector3d(-0.2, 0.9, 0.1).normalized()))};
    const BeamResponse fast = corotational_beam_response(shared, l, ends),
                       reference = corotational_beam_response(full, l, ends);
    EXPECT_GT(fast.forces.norm(), 0.0);
    EXPECT_EQ(fast.forces, reference.forces);
    EXPECT_EQ(fast.tangent_aa, reference.tangent_aa);
    EXPECT_EQ(fast.tangent_ab, reference.tangent_ab);
    EXPECT_EQ(fast.tangent_bb, reference.tangent_bb);
  }
}

TEST(NeedleBeam, BlockTridiagonalSolveAndInverseMatchADenseSolve) {
  NeedleParameters p;
  p.element_count = 30;
  const NeedleModel model = make_needle_model(p).value();
  NeedleData data = make_needle_data(model, {}).value();
  NeedleInputs inputs;
  inputs.tip_force_n = {0.0, 0.3, -0.2};
  step(model, data, inputs);  // a bent state, so that the blocks are not axis-aligned
  // Re-assemble and factor at the bent state through a second step, then compare.
  step(model, data, inputs);
  const int blocks = data.system.blocks, size = 6 * blocks;
  // The matrix as it was factored: rebuild it from L D L^T.
  Eigen::MatrixXd dense = Eigen::MatrixXd::Zero(size, size);
  for (int col = 0; col < size; ++col) {
    std::vector<double> e(static_cast<std::size_t>(size), 0.0);
    e[static_cast<std::size_t>(col)] = 1.0;
    solve_block_tridiagonal(data.system, e);
    for (int row = 0; row < size; ++row) dense(row, col) = e[static_cast<std::size_t>(row)];
  }
  const Eigen::MatrixXd a = dense.inverse();
  // A is block tridiagonal and symmetric.
  EXPECT_LT((a - a.transpose()).norm() / a.norm(), 1e-10);
  EXPECT_LT(a.block(0, 12, 6, size - 12).norm() / a.norm(), 1e-10);
  update_needle_compliance(data, 1);
  double worst = 0.0;
  for (int i = 1; i <= blocks; ++i)
    for (int j = 1; j <= blocks; ++j) {
      const Eigen::Matrix3d c = needle_compliance_block(data, i, j);
      worst = std::max(worst, (c - dense.block(6 * (i - 1), 6 * (j - 1), 3, 3)).norm() / dense.norm());
    }
  EXPECT_LT(worst, 1e-10);
}

TEST(NeedleBeam, DynamicStepsAllocateNothingAndRepeatBitwise) {
  NeedleParameters p;
  p.element_count = 30;
  const NeedleModel model = make_needle_model(p).value();
  std::uint64_t hashes[2] = {0, 0};
  for (std::uint64_t& hash : hashes) {
    NeedleData data = make_needle_data(model, {}).value();
    NeedleInputs inputs;
    testing::AllocationGuard guard;
    for (int s = 0; s < 200; ++s) {
      inputs.base.position_m = {1e-4 * s, 2e-3 * std::sin(0.05 * s), 0.0};
      const Eigen::Quaterniond q = quaternion_from_rotation_vector(Eigen::Vector3d(0.0, 0.0, 0.002 * s));
      inputs.base.rotation_wxyz = {q.w(), q.x(), q.y(), q.z()};
      inputs.tip_force_n = {0.0, 0.01, 0.0};
      step(model, data, inputs);
    }
    EXPECT_EQ(guard.allocations(), 0u);
    EXPECT_TRUE(data.health.healthy());
    EXPECT_EQ(data.steps, 200);
    hash =
        testing::bits_hash({data.positions_m, data.rotations_wxyz, data.velocities_m_s, data.angular_velocities_rad_s});
  }
  EXPECT_EQ(hashes[0], hashes[1]);
}

TEST(NeedleBeam, NaNPoseAndPoseJumpAreRejectedAndTheLastGoodStateKept) {
  const NeedleModel model = make_needle_model(NeedleParameters{}).value();
  NeedleData data = make_needle_data(model, {}).value();
  NeedleInputs inputs;
  inputs.base.position_m = {0.001, 0.0, 0.0};
  step(model, data, inputs);
  ASSERT_TRUE(data.health.healthy());
  const std::uint64_t good = testing::bits_hash({data.positions_m, data.rotations_wxyz, data.velocities_m_s});
  NeedleInputs nan_pose = inputs;
  nan_pose.base.position_m[1] = std::nan("");
  step(model, data, nan_pose);
  EXPECT_TRUE(data.health.has(HealthFlag::bad_sample));
  EXPECT_TRUE(data.report.pose_rejected);
  NeedleInputs jump = inputs;
  jump.base.position_m[0] += 2.0 * model.parameters.max_pose_jump_m;
  step(model, data, jump);
  NeedleInputs turn = inputs;  // 0.1 rad at the base swings the tip 15 mm: also a jump
  const Eigen::Quaterniond q = quaternion_from_rotation_vector(Eigen::Vector3d(0.0, 0.1, 0.0));
  turn.base.rotation_wxyz = {q.w(), q.x(), q.y(), q.z()};
  step(model, data, turn);
  NeedleInputs not_unit = inputs;
  not_unit.base.rotation_wxyz = {1.1, 0.0, 0.0, 0.0};
  step(model, data, not_unit);
  EXPECT_EQ(data.report.rejected_poses, 4);
  EXPECT_EQ(data.steps, 1);
  EXPECT_EQ(testing::bits_hash({data.positions_m, data.rotations_wxyz, data.velocities_m_s}), good);
  data.health.clear_all();
  step(model, data, inputs);  // a good pose again is taken
  EXPECT_TRUE(data.health.healthy());
  EXPECT_EQ(data.steps, 2);
}

TEST(NeedleBeam, ParametersOutOfRangeAreRefusedNamingTheField) {
  const auto field_of = [](auto change) {
    NeedleParameters p;
    change(p);
    const auto model = make_needle_model(p);
    return model.ok() ? std::string("accepted") : model.error().field;
  };
  EXPECT_EQ(field_of([](NeedleParameters& p) { p.length_m = -0.1; }), "needle.length_m");
  EXPECT_EQ(field_of([](NeedleParameters& p) { p.outer_diameter_m = std::nan(""); }), "needle.outer_diameter_m");
  EXPECT_EQ(field_of([](NeedleParameters& p) { p.inner_diameter_m = p.outer_diameter_m; }), "needle.inner_diameter_m");
  EXPECT_EQ(field_of([](NeedleParameters& p) { p.youngs_modulus_pa = 0.0; }), "needle.youngs_modulus_pa");
  EXPECT_EQ(field_of([](NeedleParameters& p) { p.bevel_angle_rad = 2.0; }), "needle.bevel_angle_rad");
  EXPECT_EQ(field_of([](NeedleParameters& p) { p.element_count = 0; }), "needle.element_count");
  EXPECT_EQ(field_of([](NeedleParameters& p) { p.step_s = 0.0; }), "needle.step_s");
  EXPECT_EQ(field_of([](NeedleParameters&) {}), "accepted");
  const NeedleModel model = make_needle_model(NeedleParameters{}).value();
  NeedlePose bad;
  bad.rotation_wxyz = {0.0, 0.0, 0.0, 0.0};
  EXPECT_EQ(make_needle_data(model, bad).error().field, "needle.base.rotation_wxyz");
}

}  // namespace
}  // namespace nav
