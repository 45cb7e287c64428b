// Writes the seed corpus of the reduced-artifact fuzz target into the folder given as
// argument: small artifacts of a one-tetrahedron mesh, one per force kind (cubature samples,
// cubic-polynomial coefficients, with and without a diaphragm lift).
#include <cstdio>
#include <filesystem>
#include <string>

#include "fuzz/seed_generator.hpp"
#include "nav/reduced/reduced_artifact.hpp"

namespace {

nav::ReducedBasis seed_basis(nav::ReducedForceKind kind, bool lift) {
  nav::TetMesh mesh;
  mesh.nodes_m = {{0, 0, 0}, {0.01, 0, 0}, {0, 0.01, 0}, {0, 0, 0.01}};
  mesh.tets = {{0, 1, 2, 3}};
  nav::ReducedBasis b;
  b.mesh_fingerprint = nav::mesh_fingerprint(mesh);
  b.node_count = 4;
  b.basis_size = 2;
  b.force_kind = kind;
  for (int i = 0; i < 24; ++i) b.basis.push_back(0.1 * i - 1.0);
  b.column_values = {0.9, 0.99};
  if (lift) b.diaphragm_lift.assign(36, 0.25);
  if (kind == nav::ReducedForceKind::stvk_cubic_polynomial) {
    b.polynomial_coefficients = {1.0, -2.0, 3.0, 0.5};
  } else if (kind != nav::ReducedForceKind::linear) {
    b.sample_tets = {0};
    b.sample_weights = {1.5};
  }
  b.training_q_bound = {0.01, 0.002};
  b.training_residual_bound = 0.05;
  return b;
}

}  // namespace

bool write_fuzz_seeds(const std::filesystem::path& folder) {
  const struct {
    const char* name;
    nav::ReducedForceKind kind;
    bool lift;
  } seeds[] = {{"linear.navrb", nav::ReducedForceKind::linear, false},
               {"corotational_lift.navrb", nav::ReducedForceKind::corotational_cubature, true},
               {"cubic.navrb", nav::ReducedForceKind::stvk_cubic_polynomial, false}};
  for (const auto& seed : seeds) {
    const std::string path = (folder / seed.name).string();
    const auto saved = nav::save_reduced_basis(path, seed_basis(seed.kind, seed.lift));
    if (!saved.ok()) {
      std::fprintf(stderr, "%s\n", saved.error().describe().c_str());
      return false;
    }
  }
  return true;
}
