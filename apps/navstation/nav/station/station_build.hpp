#pragma once
// Builds what a scene declares, and only that: the frame tree, the liver mesh and its model
// (full order, reduced, or the reduced escalation ladder), the needle (if `needle:`), the ligaments (if `ligaments:`),
// each with its data at rest, and reports their memory footprint. Init-time code: it reads files, allocates and returns
// errors that name the scene file, the section's line and its key.
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "nav/calibration/frame_tree.hpp"
#include "nav/connective/organ_ligaments.hpp"
#include "nav/core/error.hpp"
#include "nav/mesh/tet_mesh.hpp"
#include "nav/needle/needle_tissue_model.hpp"
#include "nav/reduced/reduced_ladder.hpp"
#include "nav/reduced/reduced_model.hpp"
#include "nav/station/scene.hpp"
#include "nav/tissue/tet_fem_model.hpp"

namespace nav::station {

/// The liver as built: its mesh and scene, and the model of the declared rung with its data
/// (a reduced liver with `escalation:` builds the ladder alone, not a separate reduced model).
struct LiverModels {
  TetMesh mesh;
  TissueScene scene;
  Point3 tumour_m{};  ///< the tumour's centre, model frame, inside the mesh
  std::optional<TetFemModel> full;
  std::optional<TetFemData> full_data;
  std::optional<ReducedModel> reduced;
  std::optional<ReducedData> reduced_data;
  std::optional<ReducedLadderModel> ladder;
  std::optional<ReducedLadderData> ladder_data;
};

/// Everything a station runs, built from one Scene.
struct StationModels {
  Scene scene;
  calibration::FrameTree frames;
  LiverModels liver;
  std::optional<NeedleTissueModel> needle;
  std::optional<NeedleTissueData> needle_data;
  std::optional<OrganLigaments> ligaments;
  std::optional<FrameTissueData> ligament_data;
};

/// One line of the footprint: a part of one model and its bytes.
struct FootprintLine {
  std::string model;  ///< "liver", "needle", "ligaments"
  std::string part;   ///< "mesh", "tables", "data arena", ...
  std::int64_t bytes = 0;
  bool estimated = false;  ///< from element counts, where the model does not report its size
};

/// The memory a station's models hold.
struct MemoryFootprint {
  std::vector<FootprintLine> lines;
  std::int64_t total_bytes() const;
  /// The lines of `model`'s name (empty if it was not built).
  std::int64_t model_bytes(const std::string& model) const;
};

/// A built station and its footprint.
struct BuiltStation {
  StationModels models;
  MemoryFootprint footprint;
};

/// The footprint of built models: meshes, model tables (reported by the model, or estimated
/// from its element counts) and data arenas.
MemoryFootprint measure_footprint(const StationModels& models);

/// The scene's `ligaments:` on the liver `mesh`, stepped at the liver's rate, their attachment
/// declared in `liver_scene` (its stabilising springs and room for their point forces). Errors
/// name the ligaments' line and key.
Result<OrganLigaments> make_scene_ligaments(const Scene& scene, const TetMesh& mesh, TissueScene& liver_scene);

/// The reduced rungs `scene` declares, of `mesh`: liver.model.artifact, then the escalation's
/// rungs (all of one force kind), each with the scene's reduced solver settings. Errors name
/// the artifact's key and line.
Result<std::vector<ReducedRungSpec>> load_reduced_rungs(const Scene& scene, const TetMesh& mesh);

/// The reduced model of `rung` on `mesh` and `tissue` (the element law of its force kind).
Result<ReducedModel> make_scene_reduced_model(const Scene& scene, const TetMesh& mesh, const TissueScene& tissue,
                                              const ReducedRungSpec& rung);

/// The scene's escalation ladder on `rungs` (load_reduced_rungs), `mesh` and `tissue`; with
/// full_order_on_top, the full order takes the rungs' law, step, integrator and damping.
/// Errors are placed at their scene keys.
Result<ReducedLadderModel> make_scene_ladder(const Scene& scene, const TetMesh& mesh, const TissueScene& tissue,
                                             std::span<const ReducedRungSpec> rungs);

/// Builds the models `scene` declares, on the station's liver (make_station_liver).
Result<BuiltStation> build_station(Scene scene);

/// The footprint as an aligned text table with a total.
std::string format_footprint(const MemoryFootprint& footprint);

/// This process's resident memory now (/proc/self/statm), 0 where it cannot be read.
std::int64_t resident_bytes();
/// This process's largest resident memory so far (getrusage's ru_maxrss).
std::int64_t peak_resident_bytes();

}  // namespace nav::station
