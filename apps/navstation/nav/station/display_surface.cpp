#include "nav/station/display_surface.hpp"

#include <cstdio>
#include <utility>

#include "nav/mesh/validation.hpp"

namespace nav::station {

Result<DisplaySurface> make_display_surface(const TetMesh& mesh) {
  TetMeshBoundary boundary = extract_boundary(mesh);
  if (boundary.mesh_node_of_vertex.size() > dds::kMaxSurfaceVertices)
    return Error{.message = "the liver's boundary has " + std::to_string(boundary.mesh_node_of_vertex.size()) +
                            " vertices, more than a "
                            "DeformedSurface holds (" +
                            std::to_string(dds::kMaxSurfaceVertices) + ")",
                 .field = "liver.mesh"};
  DisplaySurface surface;
  surface.nodes = std::move(boundary.mesh_node_of_vertex);
  surface.rest_m = std::move(boundary.surface.vertices_m);
  surface.triangles = std::move(boundary.surface.triangles);
  return surface;
}

std::string surface_obj(const DisplaySurface& surface) {
  std::string text = "# the station's liver surface at rest, model frame, metres\n";
  char line[160];
  for (const Point3& v : surface.rest_m) {
    std::snprintf(line, sizeof(line), "v %.9g %.9g %.9g\n", v[0], v[1], v[2]);
    text += line;
  }
  for (const auto& t : surface.triangles) {
    std::snprintf(line, sizeof(line), "f %d %d %d\n", t[0] + 1, t[1] + 1, t[2] + 1);
    text += line;
  }
  return text;
}

Result<SurfaceReconstruction> SurfaceReconstruction::create(const OperatingLoopModel& loop,
                                                            const DisplaySurface& surface) {
  auto scratch = make_liver_display_scratch(loop);
  if (!scratch.ok()) return scratch.error();
  return SurfaceReconstruction(loop, surface, std::move(scratch).value());
}

SurfaceReconstruction::SurfaceReconstruction(const OperatingLoopModel& loop, const DisplaySurface& surface,
                                             LiverDisplayScratch scratch)
    : loop_(&loop), surface_(&surface), scratch_(std::move(scratch)), displacements_m_(3 * surface.nodes.size()) {}

void SurfaceReconstruction::reconstruct(const OperatingLoopOutputs& outputs, dds::DeformedSurface& out) {
  liver_displacements_m(*loop_, outputs, scratch_, surface_->nodes, displacements_m_);
  out.source_time_ns = outputs.tissue_time_ns;
  out.surface_id = kLiverSurfaceId;
  out.vertex_count = static_cast<std::uint32_t>(surface_->nodes.size());
  for (std::size_t v = 0; v < surface_->nodes.size(); ++v)
    for (std::size_t c = 0; c < 3; ++c)
      out.vertex_positions_m[v][c] = static_cast<float>(surface_->rest_m[v][c] + displacements_m_[3 * v + c]);
}

}  // namespace nav::station
