#include "nav/mesher/mesher.hpp"

#include <cmath>
#include <optional>
#include <string>

#include "nav/mesher/boundary_slivers.hpp"
#include "nav/mesher/boundary_warp.hpp"
#include "nav/mesher/kuhn_lattice.hpp"
#include "nav/mesher/lattice_fill.hpp"
#include "nav/mesher/mesh_subset.hpp"

namespace nav {
namespace {

constexpr double kMaxLatticeCubes = 16777216.0;  // 2^24

/// An Error if `element_size_m` cannot mesh `bounds` (not positive, or too many cubes).
std::optional<Error> check_size(const Bounds3& bounds, double element_size_m) {
  if (!(element_size_m > 0.0) || !std::isfinite(element_size_m)) {
    return Error{.message = "must be positive and finite, got " + std::to_string(element_size_m),
                 .field = "element_size_m"};
  }
  double cubes = 1.0;
  for (int a = 0; a < 3; ++a) {
    const double extent_m = bounds.max_m[a] - bounds.min_m[a];
    if (!(extent_m >= 0.0) || !std::isfinite(extent_m)) {
      return Error{.message = "the domain's bounds are empty or not finite", .field = "bounds"};
    }
    cubes *= std::ceil(extent_m / element_size_m) + 2.0;
  }
  if (cubes > kMaxLatticeCubes) {
    return Error{.message = "too small for the domain: " + std::to_string(static_cast<long long>(cubes)) +
                            " grid cubes (at most 2^24)",
                 .field = "element_size_m"};
  }
  return std::nullopt;
}

}  // namespace

Result<MesherOutput> make_tet_mesh(const MeshingDomain& domain, const MesherOptions& options) {
  const double h = options.element_size_m;
  const Bounds3 bounds = domain.bounds();
  if (auto problem = check_size(bounds, h)) return *problem;

  // Staircase: the lattice elements whose centroid is inside, with room around them.
  const KuhnLattice lattice = lattice_over(bounds, h);
  LatticePatch patch = inside_with_envelope(lattice, classify_lattice_tets(lattice, domain));
  MesherOutput output;
  output.report.lattice_cubes = static_cast<std::size_t>(lattice.cubes[0] * lattice.cubes[1] * lattice.cubes[2]);
  // Nodes near the boundary go onto it first, and the choice of elements is revised.
  const WarpOptions warp{.reach_m = options.warp_reach * h, .quality_floor = options.fitting.quality_floor};
  output.report.warped_nodes = warp_to_boundary(patch.mesh, patch.inside, domain, warp);
  output.mesh = mesh_subset(patch.mesh, patch.inside);
  output.report.removed_slivers = remove_boundary_slivers(
      output.mesh, domain,
      {.crease_cosine = options.fitting.crease_cosine, .tolerance_m = options.fitting.snapped_tolerance_m});
  if (output.mesh.tets.empty()) {
    return Error{.message = "no element has its centroid inside the domain (element size too large?)",
                 .field = "element_size_m"};
  }
  // The other boundary nodes are snapped, the interior relaxed.
  const TetMeshBoundary boundary = extract_boundary(output.mesh);
  output.boundary_nodes = boundary.mesh_node_of_vertex;
  output.report.boundary_nodes = output.boundary_nodes.size();
  BoundaryToFit outer{output.boundary_nodes, {}, &domain};
  for (const auto& t : boundary.surface.triangles) {
    outer.faces.push_back({output.boundary_nodes[t[0]], output.boundary_nodes[t[1]], output.boundary_nodes[t[2]]});
  }
  output.report.fitting = fit_to_boundary(output.mesh, outer, options.fitting);
  output.report.quality = validate_tet_mesh(output.mesh);
  return output;
}

double element_size_for_tet_count_m(double volume_m3, double tet_count) {
  return std::cbrt(6.0 * volume_m3 / tet_count);
}

}  // namespace nav
