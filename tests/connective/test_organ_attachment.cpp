// Coupling of the frame-based ligaments to the liver (node positions in, nodal forces out):
// the barycentric mapping carries affine motions exactly and its transpose keeps the total
// force; the embedded liver hung by two ligaments stays finite with the stabilised staggered
// scheme and, as the ligaments stiffen to 10 MPa, approaches the liver held by fixed nodes;
// the same ligaments hold the reduced liver (a modal basis) as they hold the full-order one.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "connective/connective_test_support.hpp"
#include "nav/connective/organ_ligaments.hpp"
#include "nav/mesher/embedded_liver.hpp"
#include "nav/reduced/reduced_model.hpp"
#include "nav/reduced/reduction.hpp"
#include "nav/tissue/tet_fem_model.hpp"
#include "support/allocation_guard.hpp"

namespace nav {
namespace {

const EmbeddedLiver& liver() {
  static const EmbeddedLiver made = make_embedded_liver(kEmbeddedLiverElementSizeM);
  return made;
}

OrganLigaments ligaments(double youngs_modulus_pa, bool stabilise) {
  FrameTissueOptions options;
  options.rayleigh_mass_per_s = 1.0;
  return make_organ_ligaments(liver().mesh, testing::two_ligaments(), {youngs_modulus_pa, 0.45, 1100.0}, options,
                              {0.0, 0.0, -9.81}, stabilise)
      .value();
}

TEST(OrganAttachment, MappingCarriesAffineMotionsAndKeepsTheTotalForce) {
  const OrganLigaments held = ligaments(1e5, false);
  const TetMesh& mesh = liver().mesh;
  ASSERT_EQ(held.attachment.corners.size(), held.model.driven_frames().size());
  std::vector<double> moved(3 * mesh.nodes_m.size());
  const auto affine = [](const Point3& p, int a) {
    const double row[3][3] = {{1.01, 0.02, 0.0}, {-0.03, 0.98, 0.01}, {0.0, 0.05, 1.02}};
    return row[a][0] * p[0] + row[a][1] * p[1] + row[a][2] * p[2] + 0.001 * (a + 1);
  };
  for (std::size_t n = 0; n < mesh.nodes_m.size(); ++n)
    for (int a = 0; a < 3; ++a) moved[3 * n + static_cast<std::size_t>(a)] = affine(mesh.nodes_m[n], a);
  std::vector<double> driven(3 * held.attachment.corners.size());
  gather_attachment_positions(held.attachment, moved, driven);
  for (std::size_t d = 0; d < held.attachment.corners.size(); ++d) {
    const auto f = static_cast<std::size_t>(held.model.driven_frames()[d]);
    const Point3 rest{held.model.rest_positions_m()[3 * f], held.model.rest_positions_m()[3 * f + 1],
                      held.model.rest_positions_m()[3 * f + 2]};
    for (int a = 0; a < 3; ++a) EXPECT_NEAR(driven[3 * d + static_cast<std::size_t>(a)], affine(rest, a), 1e-12);
  }
  std::vector<double> forces(driven.size());
  for (std::size_t k = 0; k < forces.size(); ++k) forces[k] = std::sin(1.0 + static_cast<double>(k));
  std::vector<PointForce> spread(held.attachment.nodes.size());
  scatter_attachment_forces(held.attachment, forces, moved, spread);
  for (int a = 0; a < 3; ++a) {
    double given = 0.0, spread_total = 0.0;
    for (std::size_t d = 0; d < forces.size() / 3; ++d) given += forces[3 * d + static_cast<std::size_t>(a)];
    for (const PointForce& p : spread) spread_total += p.force_n[a];
    EXPECT_NEAR(spread_total, given, 1e-12);
  }
  EXPECT_EQ(held.attachment.spring_stiffness_n_m, 0.0);
  TetMesh elsewhere;
  elsewhere.nodes_m = {{1.0, 1.0, 1.0}, {1.1, 1.0, 1.0}, {1.0, 1.1, 1.0}, {1.0, 1.0, 1.1}};
  elsewhere.tets = {{0, 1, 2, 3}};
  const auto outside = attach_driven_frames(held.model, elsewhere);
  ASSERT_FALSE(outside.ok());
  EXPECT_NE(outside.error().field.find("driven frame"), std::string::npos);
}

/// The liver's scene under gravity, held by fixed nodes or by springs of stiffness k_s on the
/// attachment nodes (the stabilisation).
TissueScene liver_scene(const OrganAttachment& attachment, bool fixed) {
  TissueScene scene;
  scene.default_material = {5000.0, 0.45, 1060.0};
  scene.gravity_m_s2 = {0.0, 0.0, -9.81};
  if (fixed)
    scene.fixed_nodes = attachment.nodes;
  else
    declare_attachment(attachment, scene);
  return scene;
}

/// Implicit Euler, 10 ms, corotational unless `rotation` says otherwise.
TissueSolverOptions liver_options(ElementRotation rotation = ElementRotation::corotational) {
  TissueSolverOptions options;
  options.rotation = rotation;
  options.cg_iterations = 5;
  options.rayleigh_mass_per_s = 2.0;
  return options;
}

TetFemModel liver_model(const OrganAttachment& attachment, bool fixed) {
  return make_tet_fem_model(liver().mesh, liver_scene(attachment, fixed), liver_options()).value();
}

/// Steps the ligaments and one liver rung together, staggered, for `steps` steps: the rung
/// is given by its node positions (3 per node, refreshed by `positions()`) and its step.
/// Returns the heap allocations made by the coupled steps (none is allowed).
template <class Positions, class Advance>
std::size_t step_held(const OrganLigaments& held, int steps, Positions positions, Advance advance,
                      HealthFlags& health) {
  FrameTissueData ligament = make_frame_tissue_data(held.model).value();
  AttachmentBuffers buffers = make_attachment_buffers(held.attachment);
  TissueInputs inputs;
  const nav::testing::AllocationGuard guard;
  for (int k = 0; k < steps; ++k) {
    step_attached(held.model, ligament, held.attachment, buffers, positions(), 1.0);
    inputs.point_forces = buffers.point_forces;
    advance(inputs);
  }
  health.merge(ligament.health);
  return guard.allocations();
}

/// The liver's node displacements after `steps` steps, held by the ligaments (staggered) or,
/// without them, by the model's own supports; the health flags of both models are merged.
std::vector<double> settle(const OrganLigaments* held, const TetFemModel& model, int steps, HealthFlags& health) {
  TetFemData data = make_tet_fem_data(model).value();
  const auto advance = [&](const TissueInputs& inputs) { step(model, data, inputs); };
  if (held == nullptr) {
    for (int k = 0; k < steps; ++k) advance({});
  } else {
    EXPECT_EQ(step_held(
                  *held, steps, [&] { return std::span<const double>(data.positions_m); }, advance, health),
              0u);
  }
  health.merge(data.health);
  std::vector<double> displacement(data.positions_m.size());
  for (std::size_t i = 0; i < displacement.size(); ++i)
    displacement[i] = data.positions_m[i] - model.rest_positions_m()[i];
  return displacement;
}

double largest(const std::vector<double>& values) {
  double m = 0.0;
  for (double v : values) m = std::max(m, std::abs(v));
  return m;
}

TEST(OrganAttachment, StiffLigamentsHoldTheLiverLikeFixedNodes) {
  HealthFlags fixed_health, held_health;
  const OrganLigaments stiff = ligaments(1e7, true);
  const std::vector<double> fixed = settle(nullptr, liver_model(stiff.attachment, true), 60, fixed_health);
  const std::vector<double> held = settle(&stiff, liver_model(stiff.attachment, false), 60, held_health);
  std::vector<double> difference(fixed.size());
  for (std::size_t i = 0; i < fixed.size(); ++i) difference[i] = held[i] - fixed[i];
  std::printf(
      "liver under gravity, 0.6 s: fixed nodes %.2f mm, 10 MPa ligaments %.2f mm, largest difference %.2f mm (k_s %.0f "
      "N/m)\n",
      1e3 * largest(fixed), 1e3 * largest(held), 1e3 * largest(difference), stiff.attachment.spring_stiffness_n_m);
  EXPECT_FALSE(held_health.has(HealthFlag::non_finite_state));
  EXPECT_LT(largest(difference), 0.1 * largest(fixed));
}

TEST(OrganAttachment, StabilisedCouplingStaysBoundedWherePlainStaggeringDiverges) {
  // 200 kPa ligaments: k h^2 is about 5 times a node's mass at the attachment.
  HealthFlags plain_health, stabilised_health;
  const OrganLigaments plain = ligaments(2e5, false), stabilised = ligaments(2e5, true);
  const std::vector<double> diverging = settle(&plain, liver_model(plain.attachment, false), 25, plain_health);
  const std::vector<double> bounded =
      settle(&stabilised, liver_model(stabilised.attachment, false), 25, stabilised_health);
  std::printf("200 kPa ligaments after 25 steps: plain staggering %.3g m (health %u), stabilised %.2f mm (health %u)\n",
              largest(diverging), plain_health.bits(), 1e3 * largest(bounded), stabilised_health.bits());
  EXPECT_LT(largest(bounded), 0.05);
  EXPECT_FALSE(stabilised_health.has(HealthFlag::non_finite_state));
  EXPECT_TRUE(largest(diverging) > 1.0 || plain_health.has(HealthFlag::non_finite_state));
}

/// Training snapshots of a liver rung that ligaments hold (column-major, 3 per node each):
/// the static response of `statics` (linear, quasi-static) to gravity alone and to gravity
/// plus 0.1 N along x, y and z on each attachment node in turn.
std::vector<double> attachment_snapshots(const TetFemModel& statics, const OrganAttachment& attachment, int& count) {
  std::vector<double> snapshots;
  count = 0;
  const auto solve = [&](std::span<const PointForce> forces) {
    TetFemData data = make_tet_fem_data(statics).value();
    TissueInputs inputs;
    inputs.point_forces = forces;
    step(statics, data, inputs);
    for (std::size_t i = 0; i < data.positions_m.size(); ++i)
      snapshots.push_back(data.positions_m[i] - statics.rest_positions_m()[i]);
    ++count;
  };
  solve({});
  for (const std::int32_t node : attachment.nodes)
    for (int a = 0; a < 3; ++a) {
      PointForce force{node, {0.0, 0.0, 0.0}};
      force.force_n[static_cast<std::size_t>(a)] = 0.1;
      solve(std::span<const PointForce>(&force, 1));
    }
  return snapshots;
}

TEST(OrganAttachment, LigamentsHoldTheReducedLiverAsTheyHoldTheFullOrderOne) {
  // Linear elements on both rungs, each brought to equilibrium at every step (quasi-static)
  // under the ligaments' forces, so that the difference is the reduction's alone. The reduced
  // rung is a POD basis (r = 48) of the liver's static responses to gravity and to unit
  // forces on the attachment nodes: the coupled run itself is not in its training.
  HealthFlags full_health, reduced_health;
  const OrganLigaments held = ligaments(1e6, true);
  const TissueScene scene = liver_scene(held.attachment, false);
  TissueSolverOptions options = liver_options(ElementRotation::none);
  options.integrator = Integrator::quasi_static;
  options.rayleigh_mass_per_s = 0.0;
  const TetFemModel full = make_tet_fem_model(liver().mesh, scene, options).value();
  const std::vector<double> full_m = settle(&held, full, 60, full_health);

  int snapshot_count = 0;
  const std::vector<double> snapshots = attachment_snapshots(full, held.attachment, snapshot_count);
  ReductionOptions reduction;
  reduction.source = ReducedBasisSource::pod;
  reduction.force_kind = ReducedForceKind::linear;
  reduction.basis_size = 48;
  const ReducedBasis basis = make_pod_basis(liver().mesh, scene, options, reduction, snapshots, snapshot_count).value();
  ReducedSolverOptions reduced_options;
  reduced_options.integrator = ReducedIntegrator::quasi_static;
  reduced_options.step_s = options.step_s;
  const ReducedModel reduced = make_reduced_model(liver().mesh, scene, options, basis, reduced_options).value();
  ReducedData data = make_reduced_data(reduced).value();
  std::vector<double> reduced_m(full_m.size()), positions_m(full_m.size());
  const auto positions = [&] {
    reconstruct_all_displacements_m(reduced, data, reduced_m);
    for (std::size_t i = 0; i < positions_m.size(); ++i) positions_m[i] = full.rest_positions_m()[i] + reduced_m[i];
    return std::span<const double>(positions_m);
  };
  EXPECT_EQ(step_held(
                held, 60, positions, [&](const TissueInputs& inputs) { step(reduced, data, inputs); }, reduced_health),
            0u);
  reduced_health.merge(data.health);
  positions();

  double squared_m2 = 0.0, largest_difference_m = 0.0;
  for (std::size_t i = 0; i < full_m.size(); ++i) {
    squared_m2 += (reduced_m[i] - full_m[i]) * (reduced_m[i] - full_m[i]);
    largest_difference_m = std::max(largest_difference_m, std::abs(reduced_m[i] - full_m[i]));
  }
  const double rms_m = std::sqrt(squared_m2 / static_cast<double>(full_m.size() / 3));
  std::printf(
      "liver held by 1 MPa ligaments, 0.6 s, linear quasi-static: full order %.2f mm, reduced (r = 48) %.2f mm, "
      "difference RMS %.3f mm, largest %.2f mm\n",
      1e3 * largest(full_m), 1e3 * largest(reduced_m), 1e3 * rms_m, 1e3 * largest_difference_m);
  EXPECT_EQ(reduced_health.bits(), 0u);
  EXPECT_FALSE(full_health.has(HealthFlag::non_finite_state));
  EXPECT_LT(rms_m, 0.05 * largest(full_m));
}

}  // namespace
}  // namespace nav
