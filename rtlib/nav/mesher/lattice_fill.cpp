#include "nav/mesher/lattice_fill.hpp"

namespace nav {

std::vector<std::uint8_t> classify_lattice_tets(const KuhnLattice& lattice, const MeshingDomain& domain) {
  const auto& n = lattice.cubes;
  const double h = lattice.spacing_m;
  std::vector<std::uint8_t> inside(static_cast<std::size_t>(n[0] * n[1] * n[2] * KuhnLattice::kTetsPerCube), 0);
  std::vector<std::uint8_t> column(static_cast<std::size_t>(n[2]));
  for (std::int64_t j = 0; j < n[1]; ++j) {
    for (std::int64_t i = 0; i < n[0]; ++i) {
      for (int t = 0; t < KuhnLattice::kTetsPerCube; ++t) {
        const Point3 offset = KuhnLattice::centroid_offset(t);
        domain.classify_column(lattice.anchor_m[0] + (static_cast<double>(i - 1) + offset[0]) * h,
                               lattice.anchor_m[1] + (static_cast<double>(j - 1) + offset[1]) * h,
                               lattice.anchor_m[2] + (offset[2] - 1.0) * h, h, column);
        for (std::int64_t k = 0; k < n[2]; ++k) {
          inside[static_cast<std::size_t>(lattice.tet_index(i, j, k, t))] = column[static_cast<std::size_t>(k)];
        }
      }
    }
  }
  return inside;
}

LatticePatch inside_with_envelope(const KuhnLattice& lattice, const std::vector<std::uint8_t>& inside) {
  const auto& n = lattice.cubes;
  const auto each_tet = [&](auto&& visit) {
    for (std::int64_t k = 0; k < n[2]; ++k)
      for (std::int64_t j = 0; j < n[1]; ++j)
        for (std::int64_t i = 0; i < n[0]; ++i)
          for (int t = 0; t < KuhnLattice::kTetsPerCube; ++t)
            visit(lattice.tet_nodes(i, j, k, t), inside[static_cast<std::size_t>(lattice.tet_index(i, j, k, t))]);
  };
  // Nodes of inside tetrahedra; then the tetrahedra touching one of them.
  std::vector<std::int32_t> new_index(static_cast<std::size_t>(lattice.node_count()), -1);
  each_tet([&](const std::array<std::int64_t, 4>& tet, std::uint8_t in) {
    if (in)
      for (const std::int64_t node : tet) new_index[static_cast<std::size_t>(node)] = 0;
  });
  std::vector<std::array<std::int64_t, 4>> lattice_tets;
  LatticePatch patch;
  each_tet([&](const std::array<std::int64_t, 4>& tet, std::uint8_t in) {
    bool touches = false;
    for (const std::int64_t node : tet) touches = touches || new_index[static_cast<std::size_t>(node)] == 0;
    if (!touches) return;
    lattice_tets.push_back(tet);
    patch.inside.push_back(in);
  });
  for (const auto& tet : lattice_tets)
    for (const std::int64_t node : tet) new_index[static_cast<std::size_t>(node)] = 0;
  for (std::int64_t node = 0; node < lattice.node_count(); ++node) {
    if (new_index[static_cast<std::size_t>(node)] < 0) continue;
    new_index[static_cast<std::size_t>(node)] = static_cast<std::int32_t>(patch.mesh.nodes_m.size());
    patch.mesh.nodes_m.push_back(lattice.node_position_m(node));
  }
  patch.mesh.tets.reserve(lattice_tets.size());
  for (const auto& tet : lattice_tets) {
    patch.mesh.tets.push_back({new_index[static_cast<std::size_t>(tet[0])], new_index[static_cast<std::size_t>(tet[1])],
                               new_index[static_cast<std::size_t>(tet[2])],
                               new_index[static_cast<std::size_t>(tet[3])]});
  }
  return patch;
}

}  // namespace nav
