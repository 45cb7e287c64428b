// The online reduced model: with a complete basis its linear implicit and quasi-static steps
// equal the full-order TetFemModel's (gravity, point forces, moving springs, Rayleigh damping,
// prescribed diaphragm motion through the lift); steps never allocate, repeat bitwise, refuse
// bad inputs with the state untouched, and give the same bits with every instruction set's
// kernels; a model given other solver options steps as one built with them; reconstruction
// agrees with U q + L d.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "nav/reduced/reduced_model.hpp"
#include "nav/reduced/reduction.hpp"
#include "reduced/reduced_test_support.hpp"
#include "support/allocation_guard.hpp"
#include "support/kernel_isas.hpp"

namespace nav {
namespace {

using testing::basis_matrix;
using testing::BeamScene;
using testing::bits_hash;
using testing::nodes_where;

/// A small beam with every reduced load in use: held at x = 0, springs on y = 0, prescribed
/// at x = 2 cm when `prescribed`.
BeamScene busy_beam(bool prescribed) {
  BeamScene beam({0.02, 0.01, 0.01}, 0.005);
  for (std::int32_t node : nodes_where(beam.mesh, 1, 0.0))
    if (beam.mesh.nodes_m[static_cast<std::size_t>(node)][0] > 0.0 &&
        beam.mesh.nodes_m[static_cast<std::size_t>(node)][0] < 0.02)
      beam.scene.spring_nodes.push_back(node);
  beam.scene.spring_stiffness_n_m = 5.0;
  if (prescribed) beam.scene.prescribed_nodes = nodes_where(beam.mesh, 0, 0.02);
  return beam;
}

TissueSolverOptions linear_options(Integrator integrator, double step_s) {
  TissueSolverOptions options;
  options.rotation = ElementRotation::none;
  options.integrator = integrator;
  options.solver = LinearSolver::ldlt_warped;
  options.cg_iterations = 1;  // exact for linear elements
  options.step_s = step_s;
  options.rayleigh_mass_per_s = 0.5;
  options.rayleigh_stiffness_s = 0.002;
  return options;
}

/// Inputs of step i: a load ramp, a tip force, a moving spring frame and breathing.
TissueInputs inputs_at(int i, const PointForce& force) {
  TissueInputs inputs;
  inputs.load_scale = std::min(1.0, 0.1 * (i + 1));
  inputs.point_forces = std::span<const PointForce>(&force, 1);
  inputs.spring_frame.translation_m = {0.0, 0.001 * std::sin(0.2 * i), 0.0};
  inputs.spring_frame.rotation_wxyz = {std::cos(0.01 * i), 0.0, 0.0, std::sin(0.01 * i)};
  inputs.prescribed_displacement_m = {0.0, 0.0, 0.002 * std::sin(0.3 * i)};
  return inputs;
}

/// The complete linear-mode basis of a scene (r = free dofs).
ReducedBasis complete_basis(const BeamScene& beam, const TissueSolverOptions& solver, int free_dofs) {
  ReductionOptions options;
  options.source = ReducedBasisSource::linear_modes;
  options.force_kind = ReducedForceKind::linear;
  options.basis_size = free_dofs;
  auto basis = make_modal_basis(beam.mesh, beam.scene, solver, options);
  EXPECT_TRUE(basis.ok()) << basis.error().describe();
  return basis.value();
}

/// Largest nodal distance between the full-order state and the reduced reconstruction,
/// relative to the largest full-order displacement.
double relative_difference(const TetFemModel& full, const TetFemData& full_data, const ReducedModel& reduced,
                           const ReducedData& reduced_data) {
  std::vector<double> u(full_data.positions_m.size());
  reconstruct_all_displacements_m(reduced, reduced_data, u);
  double worst = 0.0, largest = 0.0;
  for (std::size_t i = 0; i < u.size(); ++i) {
    const double expected = full_data.positions_m[i] - full.rest_positions_m()[i];
    worst = std::max(worst, std::abs(u[i] - expected));
    largest = std::max(largest, std::abs(expected));
  }
  return worst / largest;
}

TEST(ReducedStep, CompleteBasisImplicitEulerEqualsFullOrder) {
  const BeamScene beam = busy_beam(false);
  const TissueSolverOptions solver = linear_options(Integrator::implicit_euler, 0.01);
  const TetFemModel full = make_tet_fem_model(beam.mesh, beam.scene, solver).value();
  const ReducedBasis basis = complete_basis(beam, solver, static_cast<int>(full.free_dof_count()));
  ReducedSolverOptions options;
  options.step_s = solver.step_s;
  options.rayleigh_mass_per_s = solver.rayleigh_mass_per_s;
  options.rayleigh_stiffness_s = solver.rayleigh_stiffness_s;
  const auto reduced = make_reduced_model(beam.mesh, beam.scene, solver, basis, options);
  ASSERT_TRUE(reduced.ok()) << reduced.error().describe();
  auto full_data = make_tet_fem_data(full).value();
  auto reduced_data = make_reduced_data(reduced.value()).value();
  const PointForce force{static_cast<std::int32_t>(beam.mesh.nodes_m.size() - 1), {0.0, 0.002, -0.003}};
  for (int i = 0; i < 40; ++i) {
    step(full, full_data, inputs_at(i, force));
    step(reduced.value(), reduced_data, inputs_at(i, force));
  }
  EXPECT_TRUE(full_data.health.healthy());
  EXPECT_TRUE(reduced_data.health.healthy()) << reduced_data.health.bits();
  EXPECT_LT(relative_difference(full, full_data, reduced.value(), reduced_data), 1e-9);
}

TEST(ReducedStep, CompleteBasisQuasiStaticWithDiaphragmLiftEqualsFullOrder) {
  // Without Rayleigh relaxation: the full-order relaxation resists the free nodes' motion from
  // where they were, the reduced one the motion of q, which leaves out the lift's share; the
  // equilibria they converge to are the same, and one linear Newton step reaches it.
  const BeamScene beam = busy_beam(true);
  TissueSolverOptions solver = linear_options(Integrator::quasi_static, 0.01);
  solver.rayleigh_mass_per_s = 0.0;
  solver.rayleigh_stiffness_s = 0.0;
  const TetFemModel full = make_tet_fem_model(beam.mesh, beam.scene, solver).value();
  const ReducedBasis basis = complete_basis(beam, solver, static_cast<int>(full.free_dof_count()));
  ASSERT_FALSE(basis.diaphragm_lift.empty());
  ReducedSolverOptions options;
  options.integrator = ReducedIntegrator::quasi_static;
  options.step_s = solver.step_s;
  const auto reduced = make_reduced_model(beam.mesh, beam.scene, solver, basis, options);
  ASSERT_TRUE(reduced.ok()) << reduced.error().describe();
  auto full_data = make_tet_fem_data(full).value();
  auto reduced_data = make_reduced_data(reduced.value()).value();
  const PointForce force{static_cast<std::int32_t>(beam.mesh.nodes_m.size() / 2), {0.001, 0.0, -0.002}};
  for (int i = 0; i < 12; ++i) {
    step(full, full_data, inputs_at(i, force));
    step(reduced.value(), reduced_data, inputs_at(i, force));
    EXPECT_LT(relative_difference(full, full_data, reduced.value(), reduced_data), 1e-9) << i;
  }
  // Lazy reconstruction of chosen nodes agrees with the full one.
  std::vector<double> all(3 * beam.mesh.nodes_m.size());
  reconstruct_all_displacements_m(reduced.value(), reduced_data, all);
  const std::vector<std::int32_t> chosen{3, static_cast<std::int32_t>(beam.mesh.nodes_m.size() - 1),
                                         beam.scene.prescribed_nodes[0]};
  std::vector<double> some(9);
  reconstruct_displacements_m(reduced.value(), reduced_data, chosen, some);
  for (std::size_t k = 0; k < chosen.size(); ++k)
    for (int c = 0; c < 3; ++c) EXPECT_EQ(some[3 * k + c], all[3 * static_cast<std::size_t>(chosen[k]) + c]);
  EXPECT_DOUBLE_EQ(some[8], 0.002 * std::sin(0.3 * 11));  // the prescribed node follows d exactly
}

/// A corotational cubature basis of the beam: 6 modes, ECSW on full-order gravity and tip-force snapshots.
ReducedBasis cubature_basis(const BeamScene& beam, const TissueSolverOptions& solver, ReducedForceKind kind, int size) {
  ReductionOptions options;
  options.source = ReducedBasisSource::linear_modes;
  options.force_kind = kind;
  options.basis_size = size;
  options.max_cubature_samples = 24;
  auto basis = make_modal_basis(beam.mesh, beam.scene, solver, options).value();
  const TetFemModel full = make_tet_fem_model(beam.mesh, beam.scene, solver).value();
  const PointForce force{static_cast<std::int32_t>(beam.mesh.nodes_m.size() - 1), {0.0, 0.0, -0.01}};
  const auto snapshots = testing::ramp_snapshots(full, force, 6, 0.2);
  const auto status = add_force_reduction(beam.mesh, beam.scene, solver, options, snapshots, 6, basis);
  EXPECT_TRUE(status.ok()) << status.error().describe();
  return basis;
}

TissueSolverOptions nonlinear_options(ElementLaw law) {
  TissueSolverOptions options;
  options.law = law;
  options.integrator = Integrator::quasi_static;
  options.step_s = 0.01;
  options.cg_iterations = 3;
  return options;
}

/// Runs `steps` scripted steps and returns the hash of (q, q_velocity); counts allocations.
std::uint64_t scripted_run(const ReducedModel& model, int steps, std::size_t& allocations) {
  auto data = make_reduced_data(model).value();
  const PointForce force{5, {0.0, 0.001, -0.002}};
  testing::AllocationGuard guard;
  for (int i = 0; i < steps; ++i) step(model, data, inputs_at(i, force));
  allocations = guard.allocations();
  return bits_hash({data.q, data.q_velocity});
}

TEST(ReducedStep, StepsNeverAllocateAndRepeatBitwise) {
  const BeamScene beam = busy_beam(true);
  for (ElementLaw law : {ElementLaw::linear_elastic, ElementLaw::st_venant_kirchhoff}) {
    const TissueSolverOptions solver = nonlinear_options(law);
    const ReducedForceKind kind =
        law == ElementLaw::linear_elastic ? ReducedForceKind::corotational_cubature : ReducedForceKind::stvk_cubature;
    const ReducedBasis basis = cubature_basis(beam, solver, kind, 6);
    for (ReducedIntegrator integrator : {ReducedIntegrator::implicit_euler, ReducedIntegrator::quasi_static})
      for (bool frozen : {true, false}) {
        ReducedSolverOptions options;
        options.integrator = integrator;
        options.frozen_tangent = frozen;
        options.newton_iterations = 2;
        options.step_s = 0.005;
        const auto model = make_reduced_model(beam.mesh, beam.scene, solver, basis, options);
        ASSERT_TRUE(model.ok()) << model.error().describe();
        std::size_t first_allocations = 1, second_allocations = 1;
        const std::uint64_t first = scripted_run(model.value(), 30, first_allocations);
        const std::uint64_t second = scripted_run(model.value(), 30, second_allocations);
        EXPECT_EQ(first_allocations, 0u);
        EXPECT_EQ(second_allocations, 0u);
        EXPECT_EQ(first, second);
        for (KernelIsa isa : testing::available_kernel_isas()) {  // every instruction set: the same bits
          options.kernel_isa = isa;
          const ReducedModel variant = make_reduced_model(beam.mesh, beam.scene, solver, basis, options).value();
          std::size_t allocations = 1;
          EXPECT_EQ(scripted_run(variant, 30, allocations), first) << kernel_isa_name(isa);
          EXPECT_EQ(allocations, 0u);
        }
      }
  }
}

TEST(ReducedStep, AModelGivenOtherSolverOptionsStepsAsOneBuiltWithThem) {
  const BeamScene beam = busy_beam(true);
  const TissueSolverOptions solver = nonlinear_options(ElementLaw::linear_elastic);
  const ReducedBasis basis = cubature_basis(beam, solver, ReducedForceKind::corotational_cubature, 6);
  ReducedSolverOptions implicit;
  implicit.step_s = 0.005;
  implicit.rayleigh_mass_per_s = 2.0;
  ReducedSolverOptions quasi_static;
  quasi_static.integrator = ReducedIntegrator::quasi_static;
  quasi_static.newton_iterations = 2;
  const ReducedModel dynamic = make_reduced_model(beam.mesh, beam.scene, solver, basis, implicit).value();
  const ReducedModel built = make_reduced_model(beam.mesh, beam.scene, solver, basis, quasi_static).value();
  const auto twin = with_solver_options(dynamic, quasi_static);
  ASSERT_TRUE(twin.ok()) << twin.error().describe();
  std::size_t allocations = 1;
  const std::uint64_t built_hash = scripted_run(built, 30, allocations);
  EXPECT_EQ(scripted_run(twin.value(), 30, allocations), built_hash);
  EXPECT_NE(scripted_run(dynamic, 30, allocations), built_hash);
  quasi_static.newton_iterations = 0;
  const auto refused = with_solver_options(dynamic, quasi_static);
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.error().field, "newton_iterations");
}

TEST(ReducedStep, CubicPolynomialStepsNeverAllocateAndRepeatBitwise) {
  const BeamScene beam = busy_beam(false);
  TissueSolverOptions solver = nonlinear_options(ElementLaw::st_venant_kirchhoff);
  ReductionOptions reduction;
  reduction.source = ReducedBasisSource::linear_modes;
  reduction.force_kind = ReducedForceKind::stvk_cubic_polynomial;
  reduction.basis_size = 6;
  ReducedBasis basis = make_modal_basis(beam.mesh, beam.scene, solver, reduction).value();
  const std::vector<double> snapshots(basis.basis.begin(), basis.basis.end());
  ASSERT_TRUE(add_force_reduction(beam.mesh, beam.scene, solver, reduction, snapshots, 6, basis).ok());
  for (bool frozen : {true, false}) {
    ReducedSolverOptions options;
    options.frozen_tangent = frozen;
    options.newton_iterations = 2;
    const ReducedModel model = make_reduced_model(beam.mesh, beam.scene, solver, basis, options).value();
    std::size_t first_allocations = 1, second_allocations = 1;
    const std::uint64_t first = scripted_run(model, 30, first_allocations);
    EXPECT_EQ(first_allocations, 0u);
    EXPECT_EQ(scripted_run(model, 30, second_allocations), first);
    EXPECT_EQ(second_allocations, 0u);
  }
}

TEST(ReducedStep, BadInputsAreRefusedWithTheStateUntouched) {
  const BeamScene beam = busy_beam(false);
  const TissueSolverOptions solver = nonlinear_options(ElementLaw::linear_elastic);
  const ReducedBasis basis = cubature_basis(beam, solver, ReducedForceKind::corotational_cubature, 4);
  const ReducedModel model = make_reduced_model(beam.mesh, beam.scene, solver, basis, ReducedSolverOptions{}).value();
  auto data = make_reduced_data(model).value();
  TissueInputs good;
  step(model, data, good);
  const std::uint64_t before = bits_hash({data.q, data.q_velocity});
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const PointForce bad_node{static_cast<std::int32_t>(beam.mesh.nodes_m.size()), {0.0, 0.0, 1.0}};
  const PointForce nan_force{1, {nan, 0.0, 0.0}};
  std::vector<TissueInputs> bad(5);
  bad[0].load_scale = nan;
  bad[1].point_forces = std::span<const PointForce>(&bad_node, 1);
  bad[2].point_forces = std::span<const PointForce>(&nan_force, 1);
  bad[3].spring_frame.rotation_wxyz = {0.0, 0.0, 0.0, 0.0};
  bad[4].prescribed_displacement_m = {0.0, std::numeric_limits<double>::infinity(), 0.0};
  for (const TissueInputs& inputs : bad) {
    data.health.clear_all();
    step(model, data, inputs);
    EXPECT_TRUE(data.health.has(HealthFlag::bad_sample));
    EXPECT_EQ(bits_hash({data.q, data.q_velocity}), before);
  }
  EXPECT_EQ(data.steps, 1);
}

TEST(ReducedStep, InitErrorsNameTheField) {
  const BeamScene beam = busy_beam(false);
  const TissueSolverOptions solver = nonlinear_options(ElementLaw::linear_elastic);
  ReductionOptions reduction;
  reduction.source = ReducedBasisSource::linear_modes;
  reduction.force_kind = ReducedForceKind::linear;
  reduction.basis_size = 4;
  const ReducedBasis basis = make_modal_basis(beam.mesh, beam.scene, solver, reduction).value();
  ReducedSolverOptions options;
  options.step_s = 0.0;
  EXPECT_EQ(make_reduced_model(beam.mesh, beam.scene, solver, basis, options).error().field, "step_s");
  options = {};
  options.newton_iterations = 0;
  EXPECT_EQ(make_reduced_model(beam.mesh, beam.scene, solver, basis, options).error().field, "newton_iterations");
  options = {};
  options.kernel_isa = static_cast<KernelIsa>(99);  // no such instruction set
  EXPECT_EQ(make_reduced_model(beam.mesh, beam.scene, solver, basis, options).error().field, "kernel_isa");
  const BeamScene other({0.03, 0.01, 0.01}, 0.005);
  EXPECT_EQ(make_reduced_model(other.mesh, other.scene, solver, basis, {}).error().field, "mesh_fingerprint");
  ReducedBasis skewed = basis;
  skewed.basis[3 * 20] *= 2.0;  // no longer mass-orthonormal
  for (double& value : skewed.basis) value *= 1.5;
  EXPECT_EQ(make_reduced_model(beam.mesh, beam.scene, solver, skewed, {}).error().field, "basis");
  ReducedBasis unsampled = basis;
  unsampled.force_kind = ReducedForceKind::corotational_cubature;
  EXPECT_EQ(make_reduced_model(beam.mesh, beam.scene, solver, unsampled, {}).error().field, "sample_tets");
}

}  // namespace
}  // namespace nav
