// The needle coupled to the corotational tetrahedral tissue through point forces and a
// probed compliance: the tissue carries the constraint forces, the probed compliance
// predicts the tissue's response, the multi-rate mode (tissue every 10 needle ticks) keeps
// the puncture, and coupled ticks allocate nothing.
#include <gtest/gtest.h>

#include <cmath>

#include "nav/needle/needle_step.hpp"
#include "nav/needle/tissue_coupling.hpp"
#include "nav/tissue/tet_fem_model.hpp"
#include "needle_coupling_support.hpp"
#include "needle_test_support.hpp"
#include "support/allocation_guard.hpp"
#include "tissue/tissue_test_support.hpp"

namespace nav {
namespace {

constexpr double kBoxM = 0.04, kPunctureN = 0.2;

/// A 4 cm cube of 20 kPa tissue held at its bottom face, quasi-static corotational.
struct Block {
  TetMesh mesh = testing::box_mesh({kBoxM, kBoxM, kBoxM}, 0.01);
  TetFemModel tissue = make_model(mesh);
  static TetFemModel make_model(const TetMesh& mesh) {
    TissueSolverOptions options;
    options.integrator = Integrator::quasi_static;
    options.cg_iterations = 2;
    return make_tet_fem_model(mesh, testing::held_at_bottom(mesh), options).value();
  }
};

/// The needle pointing down (-z) above the top face's centre, 5 mm off it.
NeedlePose above_block(double lowered_m) { return testing::needle_above(0.5 * kBoxM, 0.5 * kBoxM, kBoxM, lowered_m); }

NeedleTissueScene top_layer() { return testing::top_face_layer(0.5 * kBoxM, 0.5 * kBoxM, kBoxM, 0.005); }

/// Lowers the needle by `travel_m`; returns the largest contact force and the lowering at puncture.
std::pair<double, double> insert(const CoupledNeedleModel& model, CoupledNeedleData& data, double travel_m) {
  double largest_n = 0.0, at_puncture_m = -1.0;
  NeedleInputs inputs;
  for (int s = 1; s * testing::kInsertionStepM <= travel_m; ++s) {
    inputs.base = above_block(s * testing::kInsertionStepM);
    step(model, data, inputs);
    largest_n = std::max(largest_n, data.interaction.report.contact_force_n);
    if (at_puncture_m < 0.0 && data.interaction.report.punctures > 0) at_puncture_m = s * testing::kInsertionStepM;
  }
  return {largest_n, at_puncture_m};
}

TEST(NeedleCoupling, ProbedComplianceIsPositiveAndDecaysOverTheMesh) {
  const Block block;
  const auto probed = probe_tet_fem_compliance(block.tissue, {0.02, 0.02, 0.04}, 0.01);
  ASSERT_TRUE(probed.ok()) << probed.error().describe();
  std::printf("probed: %.3e m/N, correlation length %.1f mm\n", probed.value().point_compliance_m_per_n,
              1e3 * probed.value().correlation_length_m);
  EXPECT_GT(probed.value().point_compliance_m_per_n, 0.0);
  EXPECT_GT(probed.value().correlation_length_m, 0.002);
  EXPECT_LT(probed.value().correlation_length_m, kBoxM);
}

TEST(NeedleCoupling, TheTissueCarriesTheContactForceAsItsNodeResponsePredicts) {
  const Block block;
  const CoupledNeedleModel model =
      make_coupled_needle_model(NeedleParameters{}, top_layer(), block.tissue, 32, 1).value();
  CoupledNeedleData data = make_coupled_needle_data(model, above_block(0.0)).value();
  // Push until the contact force is half f_p, then compare the surface node's displacement
  // (the FEM's answer) with force times the node's response (the constraint solver's).
  NeedleInputs inputs;
  int s = 0;
  while (data.interaction.report.contact_force_n < 0.5 * kPunctureN && s < 2000) {
    inputs.base = above_block(++s * testing::kInsertionStepM);
    step(model, data, inputs);
  }
  ASSERT_LT(s, 2000);
  for (int k = 0; k < 5; ++k) step(model, data, inputs);  // let the quasi-static tissue settle
  const std::int32_t node = data.interaction.layers[0].contact.node;
  const double pushed_m = -data.displacements_m[3 * static_cast<std::size_t>(node) + 2];
  // The node's response along z to a force along z, from the tissue's rest factor.
  std::vector<double> response(3 * block.mesh.nodes_m.size()), work(2 * block.tissue.free_dof_count());
  ASSERT_TRUE(rest_step_response_m(block.tissue, node, 2, response, work));
  const double predicted_m = data.interaction.report.contact_force_n * response[3 * static_cast<std::size_t>(node) + 2];
  std::printf("surface pushed %.3f mm by the FEM, %.3f mm predicted by the node's response\n", 1e3 * pushed_m,
              1e3 * predicted_m);
  EXPECT_NEAR(pushed_m / predicted_m, 1.0, 0.05);
  EXPECT_TRUE(data.interaction.health.healthy());
}

TEST(NeedleCoupling, MultiRateTissueKeepsThePuncture) {
  const Block block;
  std::pair<double, double> results[2];
  const int ratios[2] = {1, 10};
  for (int k = 0; k < 2; ++k) {
    const CoupledNeedleModel model =
        make_coupled_needle_model(NeedleParameters{}, top_layer(), block.tissue, 32, ratios[k]).value();
    CoupledNeedleData data = make_coupled_needle_data(model, above_block(0.0)).value();
    results[k] = insert(model, data, 0.012);
    EXPECT_EQ(data.interaction.report.punctures, 1);
    EXPECT_GT(data.interaction.report.active_path_points, 0);
    EXPECT_FALSE(data.interaction.health.has(HealthFlag::non_finite_state));
  }
  std::printf("puncture after lowering %.2f mm (tissue every tick) and %.2f mm (every 10 ticks)\n",
              1e3 * results[0].second, 1e3 * results[1].second);
  for (const auto& [largest_n, at_m] : results) {
    EXPECT_NEAR(largest_n, kPunctureN, 1e-9);
    EXPECT_GT(at_m, 0.005);  // after the 5 mm gap
  }
  // The multi-rate puncture comes within one tissue period of base travel of the other.
  EXPECT_NEAR(results[1].second, results[0].second, 10 * testing::kInsertionStepM + 1e-9);
}

TEST(NeedleCoupling, CoupledTicksAllocateNothingAndRepeatBitwise) {
  const Block block;
  const CoupledNeedleModel model =
      make_coupled_needle_model(NeedleParameters{}, top_layer(), block.tissue, 32, 10).value();
  std::uint64_t hashes[2] = {0, 0};
  for (std::uint64_t& hash : hashes) {
    CoupledNeedleData data = make_coupled_needle_data(model, above_block(0.0)).value();
    testing::AllocationGuard guard;
    insert(model, data, 0.01);
    EXPECT_EQ(guard.allocations(), 0u);
    hash = testing::bits_hash({data.tissue.positions_m, data.interaction.needle.positions_m});
  }
  EXPECT_EQ(hashes[0], hashes[1]);
}

}  // namespace
}  // namespace nav
