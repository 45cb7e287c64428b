#include "nav/needle/tissue_surface.hpp"

#include <string>

#include "nav/mesh/validation.hpp"

namespace nav {

namespace {

/// extract_boundary's triangles on the mesh's own node indices.
TissueSurface on_mesh_nodes(const TetMeshBoundary& boundary) {
  TissueSurface surface;
  surface.triangles = boundary.surface.triangles;
  for (auto& triangle : surface.triangles)
    for (std::int32_t& corner : triangle) corner = boundary.mesh_node_of_vertex[static_cast<std::size_t>(corner)];
  return surface;
}

}  // namespace

TissueSurface mesh_boundary_surface(const TetMesh& mesh) { return on_mesh_nodes(extract_boundary(mesh)); }

Result<TissueSurface> region_boundary_surface(const TetMesh& mesh, std::int32_t region) {
  TetMesh part;
  part.nodes_m = mesh.nodes_m;
  for (std::size_t e = 0; e < mesh.tets.size() && e < mesh.tet_regions.size(); ++e)
    if (mesh.tet_regions[e] == region) part.tets.push_back(mesh.tets[e]);
  if (part.tets.empty())
    return Error{.message = "no element of the mesh is tagged region " + std::to_string(region), .field = "region"};
  return on_mesh_nodes(extract_boundary(part));
}

}  // namespace nav
