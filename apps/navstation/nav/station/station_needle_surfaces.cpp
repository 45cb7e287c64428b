#include "nav/station/station_needle_surfaces.hpp"

#include <limits>
#include <string>

#include "nav/mesh/geometry.hpp"
#include "nav/needle/tissue_surface.hpp"

namespace nav::station {

namespace {

/// The vertex of `surface` nearest `point_m`.
Point3 nearest_vertex_m(const TissueSurface& surface, const TetMesh& mesh, const Point3& point_m) {
  Point3 nearest = point_m;
  double best = std::numeric_limits<double>::infinity();
  for (const auto& triangle : surface.triangles)
    for (const std::int32_t node : triangle) {
      const Point3& p = mesh.nodes_m[static_cast<std::size_t>(node)];
      const double d = norm(p - point_m);
      if (d < best) best = d, nearest = p;
    }
  return nearest;
}

}  // namespace

Result<NeedleTissueScene> station_needle_interaction(const Scene& scene, const TetMesh& mesh, const Point3& tumour_m) {
  const NeedleSettings& needle = *scene.needle;
  NeedleTissueScene interaction = needle.interaction;
  for (std::size_t l = 0; l < needle.layer_surfaces.size(); ++l) {
    const std::optional<NeedleLayerSurface>& from_mesh = needle.layer_surfaces[l];
    if (!from_mesh) continue;
    Result<TissueSurface> surface = from_mesh->region < 0 ? Result<TissueSurface>(mesh_boundary_surface(mesh))
                                                          : region_boundary_surface(mesh, from_mesh->region);
    if (!surface.ok())
      return Error{.message = surface.error().message + " (the liver's mesh has no such surface)",
                   .file = scene.source_path,
                   .line = from_mesh->line,
                   .field = "needle.layers[" + std::to_string(l) + "]"};
    TissueLayer& layer = interaction.layers[l];
    layer.surface = static_cast<std::int32_t>(interaction.surfaces.size());
    layer.surface_point_m = nearest_vertex_m(surface.value(), mesh, tumour_m);
    interaction.surfaces.push_back(std::move(surface).value());
  }
  return interaction;
}

}  // namespace nav::station
