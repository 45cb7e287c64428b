// Same inputs, same bits on every architecture: deterministic tissue runs hashed and compared
// with golden values recorded on x86_64. The aarch64 build (qemu emulation in CI) must
// reproduce them exactly. It can because the build forbids fused multiply-add contraction
// (-ffp-contract=off), keeps Eigen's NEON kernels from fusing multiply-adds themselves and
// has element-sized matrix products summed coefficient by coefficient rather than by the
// blocked GEMM kernels, whose order depends on the architecture (CMakeLists.txt); SSE2 and
// NEON both hold two doubles per packet, so Eigen's vectorised sums run in the same order;
// and neither the mesher nor the steps call a libm function whose last bit may differ between
// C libraries (only +, -, *, / and sqrt, which IEEE 754 rounds exactly).
// A deliberate change to the tissue numerics (or the mesher) changes these values: record
// the new ones from this test's output on x86_64, and check that aarch64 agrees.
#include <gtest/gtest.h>

#include <cinttypes>
#include <cstdio>
#include <span>
#include <vector>

#include "nav/mesher/embedded_liver.hpp"
#include "nav/tissue/tet_fem_model.hpp"
#include "tissue/tissue_test_support.hpp"

namespace nav {
namespace {

using testing::bits_hash;

/// Inputs of step i: a ramped traction, a sliding and turning spring frame and a probe moving
/// in, from arithmetic alone (no libm call).
TissueInputs ramp_inputs(int i, const Point3& probe_start_m, std::span<const PointForce> forces) {
  const double t = 0.05 * i;
  TissueInputs inputs;
  inputs.point_forces = forces;
  inputs.traction_pa = {2.0 * t, 0.0, 1.0 - t};
  const double half_turn = 0.01 * t;  // quaternion (1, 0, s, 0) normalised by step()
  inputs.spring_frame.rotation_wxyz = {1.0, 0.0, half_turn, 0.0};
  inputs.spring_frame.translation_m = {0.0005 * t, 0.0, 0.0};
  inputs.prescribed_displacement_m = {0.0, 0.001 * t, 0.0};
  inputs.probe = {true, {probe_start_m[0], probe_start_m[1], probe_start_m[2] - 0.0004 * i}, 0.012};
  return inputs;
}

/// Positions and velocities after `steps` steps of `model` under ramp_inputs, hashed.
std::uint64_t run_hash(const TetMesh& mesh, const TissueScene& scene, const TissueSolverOptions& options, int steps,
                       const Point3& probe_start_m) {
  auto model = make_tet_fem_model(mesh, scene, options);
  EXPECT_TRUE(model.ok()) << model.error().describe();
  auto data = make_tet_fem_data(model.value());
  EXPECT_TRUE(data.ok());
  const std::vector<PointForce> forces{{3, {0.0, 0.01, 0.0}}, {11, {0.0, 0.0, -0.02}}};
  for (int i = 0; i < steps; ++i) step(model.value(), data.value(), ramp_inputs(i, probe_start_m, forces));
  EXPECT_EQ(data.value().steps, steps);
  EXPECT_FALSE(data.value().health.has(HealthFlag::non_finite_state));
  const std::uint64_t hash = bits_hash({data.value().positions_m, data.value().velocities_m_s});
  std::printf("state hash after %d steps: 0x%016" PRIx64 "\n", steps, hash);
  return hash;
}

TissueSolverOptions damped(Integrator integrator, LinearSolver solver, double step_s) {
  TissueSolverOptions options;
  options.integrator = integrator;
  options.solver = solver;
  options.step_s = step_s;
  options.cg_iterations = solver == LinearSolver::ldlt_warped ? 2 : 20;
  options.rayleigh_mass_per_s = 0.5;
  if (integrator != Integrator::explicit_central_difference) options.rayleigh_stiffness_s = 0.01;
  return options;
}

const Point3 kBoxProbeStart{0.03, 0.01, 0.03};

}  // namespace

TEST(TissueGoldenHash, BoxCorotationalImplicitLdlt) {
  const testing::BusyBoxScene box;
  const auto options = damped(Integrator::implicit_euler, LinearSolver::ldlt_warped, 0.01);
  EXPECT_EQ(run_hash(box.mesh, box.scene, options, 40, kBoxProbeStart), 0xaf9b15aabbca66a3ULL);
}

TEST(TissueGoldenHash, BoxCorotationalImplicitBlockJacobi) {
  const testing::BusyBoxScene box;
  const auto options = damped(Integrator::implicit_euler, LinearSolver::cg_block_jacobi, 0.01);
  EXPECT_EQ(run_hash(box.mesh, box.scene, options, 40, kBoxProbeStart), 0xf1cb429b3c5a39e5ULL);
}

TEST(TissueGoldenHash, BoxCorotationalQuasiStatic) {
  const testing::BusyBoxScene box;
  const auto options = damped(Integrator::quasi_static, LinearSolver::ldlt_warped, 0.01);
  EXPECT_EQ(run_hash(box.mesh, box.scene, options, 20, kBoxProbeStart), 0x569b777d24cf1004ULL);
}

TEST(TissueGoldenHash, BoxCorotationalExplicit) {
  const testing::BusyBoxScene box;
  const auto options = damped(Integrator::explicit_central_difference, LinearSolver::ldlt_warped, 2e-4);
  EXPECT_EQ(run_hash(box.mesh, box.scene, options, 200, kBoxProbeStart), 0xa135311de63a1627ULL);
}

// The embedded liver, meshed here (the mesher is part of the run), held at its attachments
// by springs, under gravity and a probe pressing down above the tumour.
TEST(TissueGoldenHash, EmbeddedLiverCorotationalImplicit) {
  const EmbeddedLiver liver = make_embedded_liver(kEmbeddedLiverElementSizeM);
  TissueScene scene;
  scene.spring_nodes = liver.attachment_nodes;
  scene.spring_stiffness_n_m = 20.0;
  scene.probe_stiffness_n_m = 500.0;
  const Point3 probe_start{liver.tumour_centre_m[0], liver.tumour_centre_m[1], liver.tumour_centre_m[2] + 0.06};
  const auto options = damped(Integrator::implicit_euler, LinearSolver::ldlt_warped, 0.01);
  EXPECT_EQ(run_hash(liver.mesh, scene, options, 10, probe_start), 0x2ad89d06b3efb759ULL);
}

}  // namespace nav
