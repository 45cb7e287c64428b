// Ligaments stepped by the operating loop: the embedded liver under gravity (a linear,
// quasi-static reduced model of 24 vibration modes, stepped every 10 ticks of 1 ms) hung by
// two 1 MPa frame-based ligaments, which nothing else holds.
// Checked: the loop's liver equals, bitwise, the stand-alone staggered coupling (the
// ligaments stepped at the liver's attachment nodes, then the reduced step with their forces),
// with and without an idle needle whose forces share the liver's (the physics of that
// coupling against the full-order liver: connective/test_organ_attachment.cpp); the ligaments
// pull the liver up; ticks never allocate and repeat bitwise; a liver whose scene does
// not declare the attachment, or leaves no room for its forces beside the needle's, is
// refused by field.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <vector>

#include "connective/connective_test_support.hpp"
#include "loop/loop_beam_support.hpp"
#include "nav/core/clock.hpp"
#include "nav/loop/operating_loop.hpp"
#include "nav/mesher/embedded_liver.hpp"
#include "nav/reduced/reduction.hpp"
#include "support/allocation_guard.hpp"

namespace nav {
namespace {

constexpr int kTissueEvery = 10;  // 100 Hz liver steps on the 1 kHz tick, the ligaments' step
constexpr double kStepS = 0.01;
constexpr int kLiverSteps = 60;  // 0.6 s
constexpr double kGravityM_S2 = 9.81;
constexpr std::size_t kNeedleForces = 8;  // the needle's share of the liver's point forces

/// The hung liver's parts and its loops, built once per process.
struct HungLiver {
  EmbeddedLiver liver = make_embedded_liver(kEmbeddedLiverElementSizeM);
  std::shared_ptr<const OrganLigaments> ligaments;
  TissueScene scene;  // the liver's, with the ligaments' attachment declared
  ReducedBasis modes;
  ReducedModel reduced{nullptr};
  ReducedKalmanModel filter;
  OperatingLoopOptions options;
  OperatingLoopNeedleOptions needle;
  HungLiver() {
    FrameTissueOptions frames;
    frames.step_s = kStepS;
    frames.rayleigh_mass_per_s = 1.0;
    ligaments = std::make_shared<const OrganLigaments>(make_organ_ligaments(liver.mesh, testing::two_ligaments(),
                                                                            {1e6, 0.45, 1100.0}, frames,
                                                                            {0.0, 0.0, -kGravityM_S2})
                                                           .value());
    scene.default_material = {5000.0, 0.45, 1060.0};
    scene.gravity_m_s2 = {0.0, 0.0, -kGravityM_S2};
    scene.max_point_forces = kNeedleForces;
    declare_attachment(ligaments->attachment, scene);
    const ReductionOptions reduction{
        .source = ReducedBasisSource::linear_modes, .force_kind = ReducedForceKind::linear, .basis_size = 24};
    modes = make_modal_basis(liver.mesh, scene, solver(), reduction).value();
    reduced = reduced_model(scene);
    ReducedKalmanOptions filter_options;
    filter_options.correction_std.assign(static_cast<std::size_t>(reduced.basis_size()), 1e-4);
    const ObservedPoint points[] = {observed_node(testing::nearest_node(liver.mesh, liver.tumour_centre_m))};
    filter = make_reduced_kalman_model(liver.mesh, modes, reduced, points, filter_options).value();
    options.tick_period_ns = kNsPerMs;
    options.tissue_every_ticks = kTissueEvery;
    options.display_latency_ns = 30 * kNsPerMs;
    // An idle needle (no pose ever arrives) 5 cm above the tumour, pointing down at it.
    needle.scene.layers.push_back({.surface_point_m = {0.0, 0.0, 0.05}});
    needle.marker_from_base = {{0.0, 0.0, 0.2},
                               Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitX(), -Eigen::Vector3d::UnitZ())};
    needle.max_point_forces = kNeedleForces;
  }
  static TissueSolverOptions solver() {
    return {.rotation = ElementRotation::none, .integrator = Integrator::quasi_static, .step_s = kStepS};
  }
  ReducedModel reduced_model(const TissueScene& on) const {
    const ReducedSolverOptions reduced_options{.integrator = ReducedIntegrator::quasi_static, .step_s = kStepS};
    return make_reduced_model(liver.mesh, on, solver(), modes, reduced_options).value();
  }
  OperatingLoopModel loop(bool with_needle) const {
    auto built = with_needle ? make_operating_loop_model(reduced, filter, options, needle, liver.mesh, ligaments)
                             : make_operating_loop_model(reduced, filter, options, ligaments);
    EXPECT_TRUE(built.ok()) << built.error().describe();
    return std::move(built).value();
  }
};

const HungLiver& hung() {
  static const HungLiver h;
  return h;
}

/// The loop's run: the liver's coordinates after each liver step, the ligaments' state at
/// the end and the allocations of its ticks.
struct LoopRun {
  std::vector<double> q;  // r per liver step
  std::vector<double> ligament_forces_n;
  std::vector<double> ligament_positions_m;
  std::int64_t needle_point_forces = -1;  // the last liver step's (with a needle)
  std::uint32_t tissue_flags = 0;
  std::size_t allocations = 0;
};

LoopRun run_loop(const OperatingLoopModel& model) {
  OperatingLoopData data = make_operating_loop_data(model).value();
  LoopRun run;
  run.q.reserve(static_cast<std::size_t>(kLiverSteps * hung().reduced.basis_size()));
  {
    const testing::AllocationGuard guard;
    for (int k = 0; k < kLiverSteps * kTissueEvery; ++k) {
      tick(model, data, static_cast<TimeNs>(k + 1) * kNsPerMs);
      run.tissue_flags |= data.outputs.tissue.bits();
      if (k % kTissueEvery == 0)
        run.q.insert(run.q.end(), data.active().liver().q.begin(), data.active().liver().q.end());
    }
    run.allocations = guard.allocations();
  }
  const OperatingLoopLigamentsData& ligaments = *data.ligaments;
  run.ligament_forces_n.assign(ligaments.tissue.driven_forces_n.begin(), ligaments.tissue.driven_forces_n.end());
  run.ligament_positions_m.assign(ligaments.tissue.positions_m.begin(), ligaments.tissue.positions_m.end());
  if (data.active().needle_model)
    run.needle_point_forces = static_cast<std::int64_t>(data.active().needle_model->point_force_count);
  return run;
}

/// The stand-alone staggered coupling, stepped by hand: each step the ligaments at the
/// liver's attachment nodes (rebuilt from q), then the reduced liver under their forces.
std::vector<double> run_stand_alone() {
  const HungLiver& h = hung();
  const OrganAttachment& attachment = h.ligaments->attachment;
  ReducedData liver = make_reduced_data(h.reduced).value();
  FrameTissueData frames = make_frame_tissue_data(h.ligaments->model).value();
  AttachmentBuffers buffers = make_attachment_buffers(attachment);
  std::vector<double> positions_m(3 * h.liver.mesh.nodes_m.size()), displacements_m(3 * attachment.nodes.size());
  std::vector<double> q;
  for (int k = 0; k < kLiverSteps; ++k) {
    reconstruct_displacements_m(h.reduced, liver, attachment.nodes, displacements_m);
    for (std::size_t n = 0; n < attachment.nodes.size(); ++n)
      for (std::size_t c = 0; c < 3; ++c)
        positions_m[3 * static_cast<std::size_t>(attachment.nodes[n]) + c] =
            h.liver.mesh.nodes_m[static_cast<std::size_t>(attachment.nodes[n])][c] + displacements_m[3 * n + c];
    step_attached(h.ligaments->model, frames, attachment, buffers, positions_m, 1.0);
    TissueInputs inputs;
    inputs.point_forces = buffers.point_forces;
    step(h.reduced, liver, inputs);
    q.insert(q.end(), liver.q.begin(), liver.q.end());
  }
  EXPECT_EQ(liver.health.bits(), 0u);
  EXPECT_EQ(frames.health.bits(), 0u);
  return q;
}

bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

TEST(OperatingLoopLigaments, TheLoopHangsTheLiverAsTheStandAloneCouplingDoes) {
  const std::vector<double> reference = run_stand_alone();
  const LoopRun plain = run_loop(hung().loop(false));
  const LoopRun needled = run_loop(hung().loop(true));
  EXPECT_TRUE(same_bits(plain.q, reference));
  EXPECT_TRUE(same_bits(needled.q, reference));  // the idle needle adds no force, the ligaments' join
  EXPECT_EQ(needled.needle_point_forces, static_cast<std::int64_t>(hung().ligaments->attachment.nodes.size()));
  EXPECT_EQ(plain.tissue_flags, 0u);
  EXPECT_EQ(needled.tissue_flags, 0u);

  double lift_n = 0.0;
  for (std::size_t k = 2; k < plain.ligament_forces_n.size(); k += 3) lift_n += plain.ligament_forces_n[k];
  double sag_m = 0.0;
  std::vector<double> displacements_m(3 * hung().liver.mesh.nodes_m.size());
  ReducedData end = make_reduced_data(hung().reduced).value();
  std::copy_n(plain.q.end() - hung().reduced.basis_size(), hung().reduced.basis_size(), end.q.begin());
  reconstruct_all_displacements_m(hung().reduced, end, displacements_m);
  for (std::size_t k = 2; k < displacements_m.size(); k += 3) sag_m = std::min(sag_m, displacements_m[k]);
  std::printf(
      "liver hung by two 1 MPa ligaments in the loop, 0.6 s: %zu attachment nodes, ligaments lift %.3f N, lowest "
      "node %.2f mm down\n",
      hung().ligaments->attachment.nodes.size(), lift_n, 1e3 * sag_m);
  EXPECT_GT(lift_n, 0.1);
  EXPECT_LT(sag_m, -1e-3);  // it hangs, held: down, by millimetres
  EXPECT_GT(sag_m, -0.03);
}

TEST(OperatingLoopLigaments, TicksNeverAllocateAndRepeatBitwise) {
  const OperatingLoopModel model = hung().loop(true);
  const LoopRun first = run_loop(model), second = run_loop(model);
  EXPECT_EQ(first.allocations, 0u);
  EXPECT_EQ(second.allocations, 0u);
  EXPECT_TRUE(same_bits(first.q, second.q));
  EXPECT_TRUE(same_bits(first.ligament_positions_m, second.ligament_positions_m));
}

TEST(OperatingLoopLigaments, ALiverThatDoesNotCarryTheAttachmentIsRefused) {
  const HungLiver& h = hung();
  TissueScene other = h.scene;  // springs of other ligaments
  other.spring_stiffness_n_m *= 0.5;
  auto unstabilised = make_operating_loop_model(h.reduced_model(other), h.filter, h.options, h.ligaments);
  ASSERT_FALSE(unstabilised.ok());
  EXPECT_EQ(unstabilised.error().field, "operating_loop.ligaments");
  EXPECT_NE(unstabilised.error().message.find("stabilising springs"), std::string::npos);

  OperatingLoopNeedleOptions greedy = h.needle;
  greedy.max_point_forces = kNeedleForces + 1;
  auto crowded = make_operating_loop_model(h.reduced, h.filter, h.options, greedy, h.liver.mesh, h.ligaments);
  ASSERT_FALSE(crowded.ok());
  EXPECT_EQ(crowded.error().field, "operating_loop.ligaments");
  EXPECT_NE(crowded.error().message.find("point forces"), std::string::npos) << crowded.error().message;
}

}  // namespace
}  // namespace nav
