#pragma once
// Shared inputs of the tissue tests: structured box meshes, node and face selections on
// planes (the state hash is support/bits_hash.hpp), and make_data for
// tests written once for every tissue model.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <span>
#include <vector>

#include "nav/mesh/tet_mesh.hpp"
#include "nav/mesh/validation.hpp"
#include "nav/mesher/kuhn_lattice.hpp"
#include "nav/tissue/mass_spring_model.hpp"
#include "nav/tissue/tet_fem_model.hpp"
#include "support/bits_hash.hpp"

namespace nav::testing {

/// The box [0, size] meshed by the structured Kuhn lattice of spacing element_size_m (which
/// must divide every side), so that its faces are exactly flat.
inline TetMesh box_mesh(const Point3& size_m, double element_size_m) {
  const KuhnLattice lattice = lattice_over({{0.0, 0.0, 0.0}, size_m}, element_size_m);
  const std::array<std::int64_t, 3> inner{std::llround(size_m[0] / element_size_m),
                                          std::llround(size_m[1] / element_size_m),
                                          std::llround(size_m[2] / element_size_m)};
  TetMesh mesh;
  std::vector<std::int32_t> compact(static_cast<std::size_t>(lattice.node_count()), -1);
  for (std::int64_t k = 1; k <= inner[2]; ++k)
    for (std::int64_t j = 1; j <= inner[1]; ++j)
      for (std::int64_t i = 1; i <= inner[0]; ++i)
        for (int t = 0; t < KuhnLattice::kTetsPerCube; ++t) {
          std::array<std::int32_t, 4> tet{};
          const auto lattice_nodes = lattice.tet_nodes(i, j, k, t);
          for (int a = 0; a < 4; ++a) {
            auto& index = compact[static_cast<std::size_t>(lattice_nodes[a])];
            if (index < 0) {
              index = static_cast<std::int32_t>(mesh.nodes_m.size());
              mesh.nodes_m.push_back(lattice.node_position_m(lattice_nodes[a]));
            }
            tet[a] = index;
          }
          mesh.tets.push_back(tet);
        }
  return mesh;
}

/// Nodes whose coordinate `axis` equals value_m (to 1 nm).
inline std::vector<std::int32_t> nodes_where(const TetMesh& mesh, int axis, double value_m) {
  std::vector<std::int32_t> nodes;
  for (std::size_t n = 0; n < mesh.nodes_m.size(); ++n)
    if (std::abs(mesh.nodes_m[n][axis] - value_m) < 1e-9) nodes.push_back(static_cast<std::int32_t>(n));
  return nodes;
}

/// Boundary triangles (mesh node indices, outward) lying in the plane coordinate `axis` = value_m.
inline std::vector<std::array<std::int32_t, 3>> faces_where(const TetMesh& mesh, int axis, double value_m) {
  const TetMeshBoundary boundary = extract_boundary(mesh);
  std::vector<std::array<std::int32_t, 3>> faces;
  for (const auto& triangle : boundary.surface.triangles) {
    bool on_plane = true;
    std::array<std::int32_t, 3> nodes{};
    for (int a = 0; a < 3; ++a) {
      on_plane = on_plane && std::abs(boundary.surface.vertices_m[triangle[a]][axis] - value_m) < 1e-9;
      nodes[a] = boundary.mesh_node_of_vertex[triangle[a]];
    }
    if (on_plane) faces.push_back(nodes);
  }
  return faces;
}

/// The largest magnitude in `values` (0 when empty).
inline double max_abs(std::span<const double> values) {
  double worst = 0.0;
  for (double v : values) worst = std::max(worst, std::abs(v));
  return worst;
}

/// The data of a model, whichever model it is.
inline Result<TetFemData> make_data(const TetFemModel& model) { return make_tet_fem_data(model); }
inline Result<MassSpringData> make_data(const MassSpringModel& model) { return make_mass_spring_data(model); }

/// A 2 x 2 x 6 cm block with every boundary condition and load in use: held at z = 0,
/// prescribed at z = 6 cm, springs on x = 0, traction on x = 2 cm, the probe active.
struct BusyBoxScene {
  TetMesh mesh = box_mesh({0.02, 0.02, 0.06}, 0.005);
  TissueScene scene;
  BusyBoxScene() {
    scene.default_material = {3.0e3, 0.45, 1000.0};
    scene.fixed_nodes = nodes_where(mesh, 2, 0.0);
    scene.prescribed_nodes = nodes_where(mesh, 2, 0.06);
    scene.spring_nodes = nodes_where(mesh, 0, 0.0);
    scene.spring_stiffness_n_m = 50.0;
    scene.traction_triangles = faces_where(mesh, 0, 0.02);
    scene.probe_stiffness_n_m = 200.0;
  }
};

}  // namespace nav::testing
