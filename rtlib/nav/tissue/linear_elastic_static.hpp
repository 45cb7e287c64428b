#pragma once
// Small-displacement linear elasticity on linear tetrahedra, solved quasi-statically with
// a sparse LDL^T factorisation: the first rung of the tissue ladder and the liver demo's
// solver. Init-time/offline code: it allocates and may fail with an Error.
#include <cstdint>
#include <vector>

#include "nav/core/error.hpp"
#include "nav/mesh/tet_mesh.hpp"
#include "nav/tissue/tissue_scene.hpp"

namespace nav {

/// The equilibrium displacement field and what it implies.
struct StaticSolution {
  std::vector<Point3> displacement_m;             // per node
  std::vector<double> von_mises_stress_pa;        // per element (constant in a linear tet)
  std::vector<double> nodal_von_mises_stress_pa;  // volume-weighted average of incident elements
  double relative_residual = 0.0;                 // |K u - f| / |f|
  std::int64_t free_dofs = 0;
};

/// Assembles K and f from the scene and loads every tissue model takes (materials, gravity,
/// fixed nodes; point forces, all scaled by loads.load_scale), eliminates the fixed nodes and
/// solves K u = f. Errors: no fixed node, an index out of range, an inverted element, a
/// singular system, and what a linear static solve does not take (prescribed or spring nodes,
/// traction, the probe, a uniform mass), naming the field.
Result<StaticSolution> solve_linear_static(const TetMesh& mesh, const TissueScene& scene, const TissueInputs& loads);

}  // namespace nav
