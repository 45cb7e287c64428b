#pragma once
// Static equilibrium of a tissue scene with any of the ladder's elastic laws, solved to a
// stated out-of-balance force, with the stress and the out-of-balance force of the answer:
// what a user would otherwise write around step() (the load ramp, the relaxation, the
// convergence test). Offline code: it allocates, takes seconds on the liver and returns rich
// errors. Not for the real-time loop.
#include <vector>

#include "nav/core/error.hpp"
#include "nav/mesh/tet_mesh.hpp"
#include "nav/tissue/tissue_scene.hpp"

namespace nav {

/// The constitutive law of a static solve.
enum class StaticLaw {
  linear,               ///< small-displacement linear elasticity
  corotational,         ///< Hooke's law in each element's polar rotation
  st_venant_kirchhoff,  ///< Green-Lagrange strain (without the incompressibility penalty)
  neo_hookean,          ///< the compressible neo-Hookean accuracy reference
};

/// Convergence settings of a static solve.
struct StaticSolveOptions {
  /// Converged when |out-of-balance force on free dofs| <= this times |every dof's force|
  /// (the loads and the reactions that carry them).
  double relative_tolerance = 1e-6;
  /// The corotational law, and the linear and St Venant-Kirchhoff laws with springs or the
  /// probe: quasi-static steps of the tissue model with the load ramped over `ramp_steps`, then
  /// steps at the full load up to `max_steps` in all. The others: Newton (newton_static.hpp).
  int ramp_steps = 20;
  int max_steps = 2000;
  /// Relaxation of each quasi-static step (Rayleigh mass damping over a 10 ms step), which keeps
  /// the corotational tangent from overshooting without moving the equilibrium.
  double relaxation_per_s = 40.0;
};

/// The equilibrium found, per node (3 values each) and per element.
struct StaticEquilibrium {
  std::vector<double> displacement_m;       ///< 3 per node
  std::vector<double> out_of_balance_n;     ///< 3 per node: loads plus elastic forces on free dofs, 0 on held ones
  std::vector<double> reaction_n;           ///< 3 per node: what the supports exert, 0 on free dofs
  std::vector<double> cauchy_stress_pa;     ///< 6 per element: xx, yy, zz, xy, yz, xz
  std::vector<double> von_mises_stress_pa;  ///< 1 per element
  double relative_out_of_balance = 0.0;     ///< as in StaticSolveOptions::relative_tolerance
  int iterations = 0;                       ///< quasi-static steps, or Newton iterations
};

/// Equilibrium of `mesh` under `scene` (materials, supports, gravity) and `loads` (point forces,
/// traction, the prescribed displacement; springs and the probe with the tissue-model laws
/// only), by Newton (solve_newton_static) where it takes the case. The out-of-balance force and
/// the stress are evaluated from each law's stress at the answer, independently of the solver.
/// Errors: what make_tet_fem_model or solve_newton_static refuse, bad options, an inverted
/// element at the answer, and no convergence within max_steps (naming the out-of-balance force
/// reached).
Result<StaticEquilibrium> solve_static(const TetMesh& mesh, const TissueScene& scene, const TissueInputs& loads,
                                       StaticLaw law, const StaticSolveOptions& options = {});

/// "linear", "corotational", "stvk" or "neo-hookean".
const char* static_law_name(StaticLaw law);

}  // namespace nav
