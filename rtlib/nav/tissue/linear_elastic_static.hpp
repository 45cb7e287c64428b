#pragma once
// Small-displacement linear elasticity on linear tetrahedra, solved quasi-statically with
// a sparse LDL^T factorisation: the first rung of the tissue ladder and the liver demo's
// solver. Init-time/offline code: it allocates and may fail with an Error.
#include <cstdint>
#include <utility>
#include <vector>

#include "nav/core/error.hpp"
#include "nav/mesh/tet_mesh.hpp"
#include "nav/tissue/elastic_material.hpp"

namespace nav {

/// Loads and supports of one quasi-static solve.
struct StaticLoadCase {
  Point3 gravity_m_s2{0.0, 0.0, -9.81};
  /// Nodes held at zero displacement (all three components).
  std::vector<std::int32_t> fixed_nodes;
  /// External forces applied to single nodes, in newtons.
  std::vector<std::pair<std::int32_t, Point3>> nodal_forces_n;
  /// Material per TetMesh::tet_regions value; elements whose region is not listed (or a
  /// mesh without regions) use `default_material`.
  std::vector<std::pair<std::int32_t, ElasticMaterial>> region_materials;
  ElasticMaterial default_material;
};

/// The equilibrium displacement field and what it implies.
struct StaticSolution {
  std::vector<Point3> displacement_m;             // per node
  std::vector<double> von_mises_stress_pa;        // per element (constant in a linear tet)
  std::vector<double> nodal_von_mises_stress_pa;  // volume-weighted average of incident elements
  double relative_residual = 0.0;                 // |K u - f| / |f|
  std::int64_t free_dofs = 0;
};

/// Assembles K and f, eliminates the fixed nodes and solves K u = f.
/// Errors: no fixed node, an index out of range, an inverted element, a singular system.
Result<StaticSolution> solve_linear_static(const TetMesh& mesh, const StaticLoadCase& load_case);

}  // namespace nav
