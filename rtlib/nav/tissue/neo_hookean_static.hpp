#pragma once
// The accuracy reference of the tissue ladder: static equilibrium of a compressible
// neo-Hookean body on the same tetrahedra, solved by full Newton to convergence with load
// increments and a line search. Init-time/offline code: it allocates, takes seconds on the
// 22k-element liver, and returns rich errors. Not for the real-time loop.
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

/// Convergence settings of the reference solve.
struct NeoHookeanOptions {
  int load_increments = 8;         ///< loads and imposed displacements are applied in equal parts
  int max_newton_iterations = 50;  ///< per increment; more is an Error
  /// Convergence: |residual on free dofs| <= this times (|external forces| + |elastic forces|).
  double relative_tolerance = 1e-8;
};

/// The equilibrium found.
struct NeoHookeanSolution {
  std::vector<double> positions_m;        ///< 3 per node
  std::vector<double> reaction_forces_n;  ///< 3 per node: what the supports exert (0 on free dofs)
  double relative_residual = 0.0;         ///< at the last increment
  int newton_iterations = 0;              ///< over all increments
};

/// Equilibrium under the scene's supports and gravity (materials and masses as in
/// make_tet_fem_model) and `loads`: point forces, traction on the scene's traction triangles
/// (dead loads on the rest area) and the prescribed displacement, plus `constraints` on single
/// components. Frame springs and the probe are not supported (prescribe the pressed nodes
/// instead). Errors: everything make_tet_fem_model refuses, springs or an active probe, a
/// constraint out of range, no convergence.
Result<NeoHookeanSolution> solve_neo_hookean_static(const TetMesh& mesh, const TissueScene& scene,
                                                    const TissueInputs& loads,
                                                    std::span<const DofConstraint> constraints,
                                                    const NeoHookeanOptions& options = {});

}  // namespace nav
