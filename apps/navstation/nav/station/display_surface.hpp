#pragma once
// The deformed liver surface for displays (nav/deformed_surface): the boundary of the
// station's liver mesh (its vertices as mesh nodes, their rest positions, its triangles),
// and its reconstruction from the loop's published reduced state. The reconstruction runs
// on the I/O thread at a display rate, never in the real-time step: it reads the outputs the
// real-time thread published (reduced coordinates and diaphragm) and evaluates the basis at
// the boundary nodes only.
#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "nav/core/error.hpp"
#include "nav/dds/samples.hpp"
#include "nav/loop/operating_loop.hpp"
#include "nav/mesh/tet_mesh.hpp"

namespace nav::station {

/// The surface id of the liver's boundary on nav/deformed_surface.
inline constexpr std::uint32_t kLiverSurfaceId = 1;

/// The liver's boundary as displays draw it.
struct DisplaySurface {
  std::vector<std::int32_t> nodes;                     ///< surface vertex -> mesh node
  std::vector<Point3> rest_m;                          ///< rest positions of the vertices (model frame)
  std::vector<std::array<std::int32_t, 3>> triangles;  ///< vertex indices, outward
};

/// The boundary of `mesh`; an error when it has more vertices than a DeformedSurface holds.
Result<DisplaySurface> make_display_surface(const TetMesh& mesh);

/// The surface's rest shape as Wavefront OBJ text (metres), the triangles displays are given
/// (navview --surface-mesh FILE --unit m).
std::string surface_obj(const DisplaySurface& surface);

/// Rebuilds the deformed surface from published outputs (I/O thread). Owns its scratch.
class SurfaceReconstruction {
 public:
  /// Scratch for `loop`'s reduced model; init-time.
  static Result<SurfaceReconstruction> create(const OperatingLoopModel& loop, const DisplaySurface& surface);
  /// The surface of the liver that `outputs` shows (at outputs.tissue_time_ns) into `out`.
  void reconstruct(const OperatingLoopOutputs& outputs, dds::DeformedSurface& out);

 private:
  SurfaceReconstruction(const OperatingLoopModel& loop, const DisplaySurface& surface, LiverDisplayScratch scratch);
  const OperatingLoopModel* loop_;
  const DisplaySurface* surface_;
  LiverDisplayScratch scratch_;
  std::vector<double> displacements_m_;
};

}  // namespace nav::station
