#pragma once
// The liver meshes and the two liver scenes that the tissue models are measured on (issue 3:
// navbench full, the mesh-convergence test): liverFine.vtu and meshes of the smooth liver
// surface, loaded with gravity or pressed 2 cm by a probe. Init-time code: it reads files,
// allocates and returns rich errors.
#include <string>
#include <vector>

#include "nav/core/error.hpp"
#include "nav/mesh/tet_mesh.hpp"
#include "nav/tissue/tissue_scene.hpp"

namespace nav {

/// The liver of `liver_dir` (the folder of liverFine.vtu and liver-smoothUV.obj, in
/// centimetres) at about `tet_count` tetrahedra: liverFine.vtu itself (22019) from 20000 up,
/// else the mesher on the smooth surface.
Result<TetMesh> load_liver_mesh(const std::string& liver_dir, int tet_count);

/// A liver scene: its supports and materials, and its inputs at full load.
struct LiverScene {
  std::string name;
  TissueScene scene;
  TissueInputs inputs;
};

/// The two scenes on `mesh`, both held in the box of the published SOFA anchor scene
/// (x in [0, 2], y in [3, 5], z in [-1, 2] cm; the 20 nodes nearest its centre on a mesh that
/// puts fewer there), E 5 kPa, nu 0.45, 1060 kg/m^3:
/// - "gravity": gravity along -y;
/// - "probe_2cm": no gravity; the surface nodes within 1 cm of the surface node farthest from
///   the box are prescribed (a rigid probe with stick contact), pushed 2 cm towards the box's
///   centre.
std::vector<LiverScene> liver_scenes(const TetMesh& mesh);

/// Centre of the held box of liver_scenes, in metres.
inline constexpr Point3 kLiverHeldCentreM{0.01, 0.04, 0.005};

}  // namespace nav
