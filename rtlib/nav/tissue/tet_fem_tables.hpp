#pragma once
// The precomputed tables of a TetFemModel, shared by its build, kernels and step. Internal
// to rtlib/nav/tissue.
#include <array>
#include <cstdint>
#include <memory>
#include <utility>
#include <vector>

#include "nav/core/error.hpp"
#include "nav/mesh/tet_mesh.hpp"
#include "nav/tissue/elastic_material.hpp"
#include "nav/tissue/sparse_ldlt.hpp"
#include "nav/tissue/tissue_scene.hpp"

namespace nav::detail {

/// What a node's motion is decided by.
enum class NodeKind : std::uint8_t { free, fixed, prescribed };

/// Per-element, per-node and solver tables of a TetFemModel.
struct TetFemTables {
  TissueSolverOptions options;
  std::int64_t node_count = 0;
  std::vector<double> rest_m;   // 3 per node
  std::vector<double> mass_kg;  // 1 per node
  std::vector<NodeKind> node_kind;
  std::vector<std::int32_t> free_index;  // node -> index among free nodes, -1 if constrained
  std::vector<std::int32_t> free_nodes;  // ascending
  std::vector<std::int32_t> fixed_nodes, prescribed_nodes, spring_nodes, probe_nodes;
  std::vector<std::int32_t> traction_nodes;  // ascending, with their share of the loaded area
  std::vector<double> traction_area_m2;
  double spring_stiffness_n_m = 0.0;
  double probe_stiffness_n_m = 0.0;
  Point3 gravity_m_s2{};
  std::size_t max_point_forces = 0;
  // The patch of a point force on node j (TissueScene::point_force_own_share): nodes
  // patch_nodes[patch_offsets[j] .. patch_offsets[j + 1]) with their weights, j first. Empty
  // when a point force stays on its node.
  std::vector<std::int32_t> patch_offsets, patch_nodes;
  std::vector<double> patch_weights;

  std::vector<std::array<std::int32_t, 4>> tets;
  std::vector<double> gradients;  // 12 per element: row a = grad of vertex a, row-major
  std::vector<double> volume_m3;
  std::vector<LameParameters> lame;

  // Implicit system A = mass_coefficient M + stiffness_coefficient K + spring_coefficient Ks.
  double mass_coefficient = 0.0;
  double stiffness_coefficient = 0.0;
  double spring_coefficient = 0.0;
  SparseLdlt factor;                     // of the rest A over free nodes (ldlt_warped)
  std::vector<double> block_inverse;     // 9 per node: inverse of the rest A's 3x3 block
  std::vector<double> diagonal_inverse;  // 3 per node: inverse of the rest A's diagonal
  double stable_step_s = 0.0;
};

/// The entries [first, last) of the patch of a point force on `node` in the tables' patch
/// arrays; an empty range when point forces stay on their nodes.
inline std::pair<std::size_t, std::size_t> point_force_patch(const TetFemTables& tables, std::size_t node) noexcept {
  if (tables.patch_offsets.empty()) return {0, 0};
  return {static_cast<std::size_t>(tables.patch_offsets[node]),
          static_cast<std::size_t>(tables.patch_offsets[node + 1])};
}

/// The element, node, support and load tables of make_tet_fem_model, without its rest system
/// (the implicit matrix, its factor and the stable step): what a static solve that assembles
/// its own tangent needs. Errors as make_tet_fem_model's.
Result<std::shared_ptr<TetFemTables>> make_tet_fem_tables(const TetMesh& mesh, const TissueScene& scene,
                                                          const TissueSolverOptions& options);

}  // namespace nav::detail
