// Same inputs, same bits on every architecture, for the reduced liver's online step (the
// cubature kernels in their lanes, the reduced tangent and its factor, the springs and the
// traction): deterministic runs hashed and compared with golden values recorded on x86_64
// (with the widest kernels the CPU runs) that the aarch64 build must reproduce (see
// test_tissue_golden_hash.cpp for what makes that possible). The basis is made here from
// polynomial fields, mass-orthonormalised by Gram-Schmidt: arithmetic and sqrt only, where
// the offline reduction's eigensolvers and SVDs would not promise the same last bits.
// A deliberate change to the reduced numerics changes these values: record the new ones from
// this test's output on x86_64, and check that aarch64 agrees.
#include <gtest/gtest.h>

#include <algorithm>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <vector>

#include "nav/reduced/reduced_model.hpp"
#include "tissue/tissue_test_support.hpp"

namespace nav {
namespace {

using testing::bits_hash;

constexpr int kFieldCount = 6;

/// Field j at a point of the beam held at z = 0: bending both ways, stretching, twisting,
/// bulging; zero at z = 0.
Point3 field(int j, const Point3& p) {
  const double x = p[0] - 0.01, y = p[1] - 0.01, z = p[2];
  switch (j) {
    case 0:
      return {z * z, 0.0, 0.0};
    case 1:
      return {0.0, z * z, 0.0};
    case 2:
      return {0.0, 0.0, z};
    case 3:
      return {-y * z, x * z, 0.0};
    case 4:
      return {z * z * z, 0.5 * z * z * z, 0.0};
    default:
      return {x * z, y * z, -z * z};
  }
}

/// A corotational cubature basis of `mesh`: the fields, mass-orthonormalised under the lumped
/// masses of `model`, and every third tetrahedron sampled with weight 3.
ReducedBasis polynomial_basis(const TetMesh& mesh, const TetFemModel& model) {
  ReducedBasis basis;
  basis.mesh_fingerprint = mesh_fingerprint(mesh);
  basis.node_count = static_cast<std::int32_t>(mesh.nodes_m.size());
  basis.basis_size = kFieldCount;
  basis.source = ReducedBasisSource::modal_derivatives;
  basis.force_kind = ReducedForceKind::corotational_cubature;
  const std::size_t n3 = 3 * mesh.nodes_m.size();
  const auto masses = model.nodal_masses_kg();
  const auto mass_dot = [&](const double* a, const double* b) {
    double sum = 0.0;
    for (std::size_t i = 0; i < n3; ++i) sum += masses[i / 3] * a[i] * b[i];
    return sum;
  };
  basis.basis.assign(n3 * kFieldCount, 0.0);
  for (int j = 0; j < kFieldCount; ++j) {
    double* column = basis.basis.data() + n3 * static_cast<std::size_t>(j);
    for (std::size_t node = 0; node < mesh.nodes_m.size(); ++node) {
      const Point3 value = field(j, mesh.nodes_m[node]);
      for (int c = 0; c < 3; ++c) column[3 * node + c] = value[c];
    }
    for (int k = 0; k < j; ++k) {
      const double* earlier = basis.basis.data() + n3 * static_cast<std::size_t>(k);
      const double projection = mass_dot(column, earlier);
      for (std::size_t i = 0; i < n3; ++i) column[i] -= projection * earlier[i];
    }
    const double norm = std::sqrt(mass_dot(column, column));
    for (std::size_t i = 0; i < n3; ++i) column[i] /= norm;
  }
  basis.column_values.assign(kFieldCount, 0.0);
  for (std::size_t e = 0; e < mesh.tets.size(); e += 3) {
    basis.sample_tets.push_back(static_cast<std::int32_t>(e));
    basis.sample_weights.push_back(3.0);
  }
  return basis;
}

/// The beam of the busy box held at z = 0, pulled by springs at its free end, under gravity and
/// a traction on one side.
struct ReducedBeam {
  testing::BusyBoxScene box;
  TissueScene scene;
  ReducedBeam() {
    scene.default_material = box.scene.default_material;
    scene.fixed_nodes = box.scene.fixed_nodes;
    scene.spring_nodes = box.scene.prescribed_nodes;  // the free end, pulled towards a moving frame
    scene.spring_stiffness_n_m = 5.0;
    scene.traction_triangles = box.scene.traction_triangles;
    scene.gravity_m_s2 = {0.0, -9.81, 0.0};
  }
};

/// q and its rates after `steps` steps of a reduced model of the beam under ramped point
/// forces, traction and a turning spring frame, with the displacements of every node, hashed.
std::uint64_t run_hash(const ReducedSolverOptions& options, int steps) {
  const ReducedBeam beam;
  const TissueSolverOptions solver;
  auto full = make_tet_fem_model(beam.box.mesh, beam.scene, solver);
  EXPECT_TRUE(full.ok()) << full.error().describe();
  const ReducedBasis basis = polynomial_basis(beam.box.mesh, full.value());
  auto model = make_reduced_model(beam.box.mesh, beam.scene, solver, basis, options);
  EXPECT_TRUE(model.ok()) << model.error().describe();
  auto data = make_reduced_data(model.value());
  EXPECT_TRUE(data.ok());
  const std::vector<std::int32_t>& end = beam.scene.spring_nodes;
  const std::vector<PointForce> forces{{end.front(), {0.0, 0.01, 0.0}}, {end.back(), {0.02, 0.0, -0.01}}};
  for (int i = 0; i < steps; ++i) {
    const double t = 0.05 * i;
    TissueInputs inputs;
    inputs.point_forces = forces;
    inputs.load_scale = t;
    inputs.traction_pa = {1.0 * t, 0.0, 0.5 - t};
    inputs.spring_frame.rotation_wxyz = {1.0, 0.0, 0.0, 0.01 * t};  // normalised by step()
    inputs.spring_frame.translation_m = {0.001 * t, 0.0, 0.0};
    step(model.value(), data.value(), inputs);
  }
  EXPECT_EQ(data.value().steps, steps);
  EXPECT_FALSE(data.value().health.has(HealthFlag::non_finite_state));
  std::vector<double> displacements_m(3 * beam.box.mesh.nodes_m.size());
  reconstruct_all_displacements_m(model.value(), data.value(), displacements_m);
  double largest_m = 0.0;
  for (const double value : displacements_m) largest_m = std::max(largest_m, std::abs(value));
  EXPECT_GT(largest_m, 1e-4);  // a run that moves the beam, so that its hash means something
  EXPECT_LT(largest_m, 1e-2);
  const std::uint64_t hash = bits_hash({data.value().q, data.value().q_velocity, displacements_m});
  std::printf("reduced state hash after %d steps: 0x%016" PRIx64 " (largest displacement %.3f mm)\n", steps, hash,
              1e3 * largest_m);
  return hash;
}

}  // namespace

TEST(ReducedGoldenHash, BeamCorotationalCubatureImplicitFrozenTangent) {
  ReducedSolverOptions options;
  options.step_s = 0.01;
  options.rayleigh_mass_per_s = 0.5;
  options.rayleigh_stiffness_s = 0.01;
  EXPECT_EQ(run_hash(options, 40), 0xb42bf5a4e70935dcULL);
}

TEST(ReducedGoldenHash, BeamCorotationalCubatureQuasiStaticRebuiltTangent) {
  ReducedSolverOptions options;
  options.integrator = ReducedIntegrator::quasi_static;
  options.step_s = 0.01;
  options.newton_iterations = 2;
  options.frozen_tangent = false;
  options.rayleigh_mass_per_s = 5.0;
  EXPECT_EQ(run_hash(options, 20), 0xa047cb8fb0e7051fULL);
}

}  // namespace nav
