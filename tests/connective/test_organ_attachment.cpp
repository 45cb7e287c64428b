// Coupling of the frame-based ligaments to the liver (node positions in, nodal forces out):
// the barycentric mapping carries affine motions exactly and its transpose keeps the total
// force; the embedded liver hung by two ligaments stays finite with the stabilised staggered
// scheme and, as the ligaments stiffen to 10 MPa, approaches the liver held by fixed nodes.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "nav/connective/organ_ligaments.hpp"
#include "nav/mesher/embedded_liver.hpp"
#include "nav/tissue/tet_fem_model.hpp"

namespace nav {
namespace {

const EmbeddedLiver& liver() {
  static const EmbeddedLiver made = make_embedded_liver(kEmbeddedLiverElementSizeM);
  return made;
}

/// Two 3 x 3 cm ligaments, 3 cm long, over the right lobe and the left of the falciform plane.
std::vector<LigamentSpec> two_ligaments() {
  std::vector<LigamentSpec> specs(2);
  specs[0].footprint_centre_m = {-0.045, 0.0, 0.0};
  specs[1].footprint_centre_m = {0.035, 0.015, 0.0};
  for (LigamentSpec& spec : specs) spec.embed_m = 0.006;
  return specs;
}

OrganLigaments ligaments(double youngs_modulus_pa, bool stabilise) {
  FrameTissueOptions options;
  options.rayleigh_mass_per_s = 1.0;
  return make_organ_ligaments(liver().mesh, two_ligaments(), {youngs_modulus_pa, 0.45, 1100.0}, options, {0.0, 0.0, -9.81}, stabilise)
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
    const Point3 rest{held.model.rest_positions_m()[3 * f], held.model.rest_positions_m()[3 * f + 1], held.model.rest_positions_m()[3 * f + 2]};
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

/// The liver, implicit Euler corotational, held by fixed nodes or by springs of stiffness k_s
/// on the attachment nodes (the stabilisation), under gravity.
TetFemModel liver_model(const OrganAttachment& attachment, bool fixed) {
  TissueScene scene;
  scene.default_material = {5000.0, 0.45, 1060.0};
  scene.gravity_m_s2 = {0.0, 0.0, -9.81};
  if (fixed)
    scene.fixed_nodes = attachment.nodes;
  else
    declare_attachment(attachment, scene);
  TissueSolverOptions options;
  options.cg_iterations = 5;
  options.rayleigh_mass_per_s = 2.0;
  return make_tet_fem_model(liver().mesh, scene, options).value();
}

/// The liver's node displacements after `steps` steps, held by the ligaments (staggered) or,
/// without them, by the model's own supports; the health flags of both models are merged.
std::vector<double> settle(const OrganLigaments* held, const TetFemModel& model, int steps, HealthFlags& health) {
  TetFemData data = make_tet_fem_data(model).value();
  if (held == nullptr) {
    for (int k = 0; k < steps; ++k) step(model, data, {});
  } else {
    FrameTissueData ligament = make_frame_tissue_data(held->model).value();
    AttachmentBuffers buffers = make_attachment_buffers(held->attachment);
    TissueInputs inputs;
    for (int k = 0; k < steps; ++k) {
      step_attached(held->model, ligament, held->attachment, buffers, data.positions_m, 1.0);
      inputs.point_forces = buffers.point_forces;
      step(model, data, inputs);
    }
    health.merge(ligament.health);
  }
  health.merge(data.health);
  std::vector<double> displacement(data.positions_m.size());
  for (std::size_t i = 0; i < displacement.size(); ++i) displacement[i] = data.positions_m[i] - model.rest_positions_m()[i];
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
  std::printf("liver under gravity, 0.6 s: fixed nodes %.2f mm, 10 MPa ligaments %.2f mm, largest difference %.2f mm (k_s %.0f N/m)\n",
              1e3 * largest(fixed), 1e3 * largest(held), 1e3 * largest(difference), stiff.attachment.spring_stiffness_n_m);
  EXPECT_FALSE(held_health.has(HealthFlag::non_finite_state));
  EXPECT_LT(largest(difference), 0.1 * largest(fixed));
}

TEST(OrganAttachment, StabilisedCouplingStaysBoundedWherePlainStaggeringDiverges) {
  // 200 kPa ligaments: k h^2 is about 5 times a node's mass at the attachment.
  HealthFlags plain_health, stabilised_health;
  const OrganLigaments plain = ligaments(2e5, false), stabilised = ligaments(2e5, true);
  const std::vector<double> diverging = settle(&plain, liver_model(plain.attachment, false), 25, plain_health);
  const std::vector<double> bounded = settle(&stabilised, liver_model(stabilised.attachment, false), 25, stabilised_health);
  std::printf("200 kPa ligaments after 25 steps: plain staggering %.3g m (health %u), stabilised %.2f mm (health %u)\n", largest(diverging),
              plain_health.bits(), 1e3 * largest(bounded), stabilised_health.bits());
  EXPECT_LT(largest(bounded), 0.05);
  EXPECT_FALSE(stabilised_health.has(HealthFlag::non_finite_state));
  EXPECT_TRUE(largest(diverging) > 1.0 || plain_health.has(HealthFlag::non_finite_state));
}

}  // namespace
}  // namespace nav
