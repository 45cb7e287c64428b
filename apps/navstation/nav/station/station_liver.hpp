#pragma once
// The liver a running station navigates in, built from a scene at start-up: its mesh (the
// generated liver or a mesh file), its supports and diaphragm, and its tumour as an observed
// point; and the breathing geometry the simulated devices and the loop share. The same liver
// is what `navstation --check` builds its models on. Init-time code.
#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "nav/core/error.hpp"
#include "nav/fusion/reduced_kalman.hpp"
#include "nav/mesh/tet_mesh.hpp"
#include "nav/station/scene.hpp"
#include "nav/tissue/tissue_scene.hpp"

namespace nav::station {

/// How the respiratory marker and the diaphragm move together: the marker rises along the
/// tracker's z from its mean, the diaphragm follows by diaphragm_per_marker.
struct BreathingGeometry {
  Eigen::Vector3d marker_rest_m{0.0, 0.15, 0.1};        ///< the marker at mid-breath (tracker frame)
  Eigen::Vector3d diaphragm_per_marker{0.0, 0.0, 1.0};  ///< diaphragm displacement per metre of marker motion
};

/// The station's liver: mesh, tissue scene (supports, a prescribed diaphragm, no gravity: the
/// mesh is the liver's shape in the body, already under gravity) and the tumour.
struct StationLiver {
  TetMesh mesh;
  TissueScene scene;
  Point3 tumour_m{};     ///< the tumour's centre at rest, model frame
  ObservedPoint tumour;  ///< the same point as a barycentric point of one tetrahedron
};

/// The liver mesh of `scene` alone, as the station builds it (the generated liver or the mesh
/// file): what a display needs to draw the station's surface. Errors as make_station_liver's.
Result<TetMesh> make_station_mesh(const Scene& scene);

/// The liver of `scene`: the generated liver (its own tumour unless liver.tumour_m) or the
/// mesh file, on the scene's material. Supports: the generated liver on the full-order rung is
/// held at its attachments, the top 2 cm of its boundary the diaphragm; a mesh file, and every
/// reduced liver, get the supports and diaphragm `navtool reduce` trains on
/// (liver_reduction_scene: anchored, a diaphragm patch at the top), so that an artifact meets
/// the constraints it was trained for. Its training's gravity loads only widen its basis and
/// envelope.
/// Errors name the scene file, the `liver` line and the key (liver.mesh, liver.tumour_m, ...).
Result<StationLiver> make_station_liver(const Scene& scene);

}  // namespace nav::station
