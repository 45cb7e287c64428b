#pragma once
// The station's needle layers on its liver: the layers a scene declares as surfaces of the
// mesh (`surface: capsule | tumour`, `region: N`) get their triangles from the liver's mesh.
#include "nav/core/error.hpp"
#include "nav/needle/needle_tissue_scene.hpp"
#include "nav/station/scene.hpp"

namespace nav::station {

/// The scene's needle interaction on the liver `mesh` (its tumour's centre at `tumour_m`): each layer declared as a
/// surface of the mesh takes its triangles (the capsule: the mesh's boundary; a region: the boundary of the elements
/// tagged with it), and as its surface_point_m (where a full-order liver without a rest factor is probed) its vertex
/// nearest the tumour. Errors name the layer's line.
Result<NeedleTissueScene> station_needle_interaction(const Scene& scene, const TetMesh& mesh, const Point3& tumour_m);

}  // namespace nav::station
