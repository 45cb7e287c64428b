// The memory footprint of a built station: what each model reports (ReducedModel's
// memory_bytes, every data arena's capacity), and estimates from element counts where a
// model does not report its tables (the full order, the ladder's transfer to it).
#include <sys/resource.h>
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <string>

#include "nav/station/station_build.hpp"

namespace nav::station {

namespace {

std::int64_t mesh_bytes(const TetMesh& mesh) {
  return static_cast<std::int64_t>(mesh.nodes_m.size() * sizeof(Point3) + mesh.tets.size() * sizeof(mesh.tets[0]) +
                                   mesh.tet_regions.size() * sizeof(std::int32_t));
}

/// TetFemModel's tables from its counts: per node the rest position, mass, 3x3 block
/// inverse, diagonal inverse and indices (about 140 bytes); per element the corners,
/// shape gradients, volume and Lamé pair (136 bytes); and the LDL^T factor as it is held.
std::int64_t tet_fem_table_estimate(const TetFemModel& model) {
  return 140 * model.node_count() + 136 * model.tet_count() + model.factor_bytes();
}

std::int64_t arena_bytes(const Arena& arena) { return static_cast<std::int64_t>(arena.capacity_bytes()); }

/// The ladder's full-order transfer, estimated from its sizes: the top basis and lift as rows
/// and the dof masses (3 n (r_top + 4) doubles).
std::int64_t full_order_transfer_estimate(const ReducedLadderModel& ladder) {
  const std::int64_t top_r = ladder.reduced_rung(ladder.reduced_rung_count() - 1).basis_size();
  return 3 * ladder.node_count() * (top_r + 4) * static_cast<std::int64_t>(sizeof(double));
}

/// Each rung's tables and data arena, the transfer operators and the ladder's own arena.
void add_ladder(const ReducedLadderModel& ladder, const ReducedLadderData& data, MemoryFootprint& f) {
  for (int k = 0; k < ladder.reduced_rung_count(); ++k) {
    const std::string rung = "rung " + std::to_string(k) + " ";
    f.lines.push_back({"liver", rung + "reduced tables", ladder.reduced_rung(k).memory_bytes(), false});
    f.lines.push_back(
        {"liver", rung + "data arena", arena_bytes(data.reduced[static_cast<std::size_t>(k)].arena), false});
  }
  if (ladder.has_full_order()) {
    const std::string rung = "rung " + std::to_string(ladder.reduced_rung_count()) + " ";
    f.lines.push_back({"liver", rung + "full-order tables", tet_fem_table_estimate(ladder.full_order()), true});
    f.lines.push_back({"liver", rung + "data arena", arena_bytes(data.full->arena), false});
  }
  std::int64_t transfer_bytes = 0;  // between neighbouring reduced rungs, as the ladder holds them
  for (int k = 0; k + 1 < ladder.reduced_rung_count(); ++k)
    transfer_bytes += static_cast<std::int64_t>(ladder.transfer(k).size_bytes());
  f.lines.push_back({"liver", "ladder transfers", transfer_bytes, false});
  if (ladder.has_full_order())
    f.lines.push_back({"liver", "ladder full-order transfer", full_order_transfer_estimate(ladder), true});
  f.lines.push_back({"liver", "ladder data arena", arena_bytes(data.arena), false});
}

}  // namespace

std::int64_t MemoryFootprint::total_bytes() const {
  std::int64_t total = 0;
  for (const FootprintLine& line : lines) total += line.bytes;
  return total;
}

std::int64_t MemoryFootprint::model_bytes(const std::string& model) const {
  std::int64_t total = 0;
  for (const FootprintLine& line : lines)
    if (line.model == model) total += line.bytes;
  return total;
}

MemoryFootprint measure_footprint(const StationModels& models) {
  MemoryFootprint f;
  const LiverModels& liver = models.liver;
  f.lines.push_back({"liver", "mesh", mesh_bytes(liver.mesh), false});
  if (liver.full) {
    f.lines.push_back({"liver", "full-order tables", tet_fem_table_estimate(*liver.full), true});
    f.lines.push_back({"liver", "full-order data arena", arena_bytes(liver.full_data->arena), false});
  }
  if (liver.reduced) {
    f.lines.push_back({"liver", "reduced tables", liver.reduced->memory_bytes(), false});
    f.lines.push_back({"liver", "reduced data arena", arena_bytes(liver.reduced_data->arena), false});
  }
  if (liver.ladder) add_ladder(*liver.ladder, *liver.ladder_data, f);
  if (models.needle) {
    const NeedleTissueModel& needle = *models.needle;
    const auto tables = sizeof(NeedleTissueModel) + needle.tissue_rest_m.size() * sizeof(double) +
                        needle.scene.layers.size() * sizeof(TissueLayer);
    f.lines.push_back({"needle", "tables", static_cast<std::int64_t>(tables), false});
    if (!needle.surface_bvhs.empty()) {
      std::size_t surfaces = 0;
      const auto bytes = [](const auto& v) { return v.size() * sizeof(v[0]); };
      for (const TissueSurface& surface : needle.scene.surfaces) surfaces += bytes(surface.triangles);
      for (const nav::detail::SurfaceBvh& b : needle.surface_bvhs)
        surfaces += bytes(b.triangles) + bytes(b.corners) + bytes(b.neighbours) + bytes(b.vertex_nodes) +
                    bytes(b.vertex_face_begin) + bytes(b.vertex_faces) + bytes(b.nodes);
      f.lines.push_back({"needle", "surface hierarchies", static_cast<std::int64_t>(surfaces), false});
    }
    f.lines.push_back({"needle", "beam data arena", arena_bytes(models.needle_data->needle.arena), false});
    f.lines.push_back({"needle", "interaction data arena", arena_bytes(models.needle_data->arena), false});
  }
  if (models.ligaments) {
    const OrganAttachment& a = models.ligaments->attachment;
    const auto attachment = a.corners.size() * (sizeof(a.corners[0]) + sizeof(a.barycentric[0]) + sizeof(a.slots[0])) +
                            a.nodes.size() * (sizeof(std::int32_t) + 3 * sizeof(double));
    f.lines.push_back({"ligaments", "attachment", static_cast<std::int64_t>(attachment), false});
    f.lines.push_back({"ligaments", "frame data arena", arena_bytes(models.ligament_data->arena), false});
  }
  return f;
}

std::string format_footprint(const MemoryFootprint& footprint) {
  std::string text;
  char line[160];
  std::snprintf(line, sizeof line, "%-10s %-24s %14s\n", "model", "part", "bytes");
  text += line;
  for (const FootprintLine& entry : footprint.lines) {
    std::snprintf(line, sizeof line, "%-10s %-24s %13lld%s\n", entry.model.c_str(), entry.part.c_str(),
                  static_cast<long long>(entry.bytes), entry.estimated ? "~" : " ");
    text += line;
  }
  std::snprintf(line, sizeof line, "%-35s %13lld  (%.2f MiB; ~ estimated from element counts)\n", "total",
                static_cast<long long>(footprint.total_bytes()),
                static_cast<double>(footprint.total_bytes()) / (1024.0 * 1024.0));
  text += line;
  return text;
}

std::int64_t resident_bytes() {
  std::ifstream statm("/proc/self/statm");
  long long pages = 0, resident_pages = 0;
  if (!(statm >> pages >> resident_pages)) return 0;
  return static_cast<std::int64_t>(resident_pages) * sysconf(_SC_PAGESIZE);
}

std::int64_t peak_resident_bytes() {
  rusage usage{};
  if (getrusage(RUSAGE_SELF, &usage) != 0) return 0;
  return static_cast<std::int64_t>(usage.ru_maxrss) * 1024;  // kilobytes on Linux
}

}  // namespace nav::station
