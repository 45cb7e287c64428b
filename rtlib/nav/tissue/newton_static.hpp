#pragma once
// Static equilibrium of a hyperelastic body on the tetrahedra, solved by full Newton to
// convergence with load increments (halved where Newton fails) and a line search, each tangent
// factored by SparseCholesky in a sparsity pattern built once: the compressible neo-Hookean
// accuracy reference of the tissue ladder, and the linear and St Venant-Kirchhoff static solves.
// Init-time/offline code: it allocates, takes a second on the 22k-element liver, and returns
// rich errors. Not for the real-time loop.
#include <cstdint>
#include <span>
#include <vector>

#include "nav/core/error.hpp"
#include "nav/mesh/tet_mesh.hpp"
#include "nav/tissue/tissue_scene.hpp"

namespace nav {

/// One displacement component of one node held at a value: with the other components free,
/// a roller support (symmetry planes, the lateral faces of a uniaxial test).
struct DofConstraint {
  std::int32_t node = 0;
  int axis = 0;  ///< 0, 1, 2 for x, y, z
  double displacement_m = 0.0;
};

/// The hyperelastic laws a Newton solve takes.
enum class NewtonLaw {
  linear,               ///< small-displacement linear elasticity (one iteration)
  st_venant_kirchhoff,  ///< Green-Lagrange strain, without an incompressibility penalty
  neo_hookean,          ///< the compressible neo-Hookean accuracy reference (neo_hookean.hpp)
};

/// Law and convergence settings of a Newton solve.
struct NewtonStaticOptions {
  NewtonLaw law = NewtonLaw::neo_hookean;
  /// Loads and imposed displacements are applied in this many equal parts at first; an
  /// increment on which Newton fails is halved, at most max_cutbacks times in all.
  int load_increments = 1;
  int max_cutbacks = 8;
  int max_newton_iterations = 50;  ///< per increment; more fails the increment
  /// Convergence: |residual on free dofs| <= this times (|external forces| + |elastic forces|).
  double relative_tolerance = 1e-8;
};

/// The equilibrium found.
struct NewtonStaticSolution {
  std::vector<double> positions_m;        ///< 3 per node
  std::vector<double> reaction_forces_n;  ///< 3 per node: what the supports exert (0 on free dofs)
  double relative_residual = 0.0;         ///< at the last increment
  int newton_iterations = 0;              ///< over all increments, the failed ones included
  int cutbacks = 0;                       ///< increments halved
};

/// Equilibrium under the scene's supports and gravity (materials and masses as in
/// make_tet_fem_model) and `loads`: point forces, traction on the scene's traction triangles
/// (dead loads on the rest area) and the prescribed displacement, plus `constraints` on single
/// components. Frame springs and the probe are not supported (prescribe the pressed nodes
/// instead). Errors: everything make_tet_fem_model refuses, springs or an active probe, a
/// constraint out of range, no convergence within max_cutbacks.
Result<NewtonStaticSolution> solve_newton_static(const TetMesh& mesh, const TissueScene& scene,
                                                 const TissueInputs& loads, std::span<const DofConstraint> constraints,
                                                 const NewtonStaticOptions& options = {});

}  // namespace nav
