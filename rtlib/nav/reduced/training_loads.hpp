#pragma once
// The full-order runs a reduced basis is trained on, and the held-out runs it is judged on:
// seeded, deterministic sets of static loads on a mesh and scene (gravity at several scales and
// directions, probe pushes at sampled surface points, needle-like point forces at sampled
// nodes, diaphragm displacements), each solved to static equilibrium with the full-order
// corotational TetFemModel (quasi-static Newton steps under a load ramp). Init-time/offline
// code: it allocates, takes seconds on the 22k-element liver and returns rich errors.
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "nav/core/error.hpp"
#include "nav/mesh/tet_mesh.hpp"
#include "nav/reduced/reduced_basis.hpp"
#include "nav/reduced/reduced_model.hpp"
#include "nav/tissue/tissue_scene.hpp"

namespace nav {

/// One static load case, owning what a TissueInputs points at.
struct TrainingLoad {
  std::string name;                      ///< "gravity 2", "push 5", ... for reports
  Point3 gravity_m_s2{};                 ///< replaces the scene's gravity for this load
  std::vector<PointForce> point_forces;  ///< a probe's or a needle tip's patch of forces
  Point3 prescribed_displacement_m{};    ///< of the scene's diaphragm nodes

  /// The inputs at `fraction` of this load (load_scale and prescribed displacement scaled).
  TissueInputs inputs(double fraction = 1.0) const;
};

/// How many loads of each kind, and how large. Magnitudes are the largest of a training set;
/// held-out loads stay inside them (interpolation, not extrapolation).
struct TrainingLoadOptions {
  std::uint64_t seed = 1;
  std::vector<double> gravity_scales{0.5, 1.0};  ///< along the scene's gravity
  int gravity_tilts = 3;                         ///< full-gravity loads tilted from the scene's direction
  double gravity_tilt_rad = 0.35;                ///< by this angle, about sampled axes
  int probe_pushes = 8;                          ///< at sampled surface points, along the inward normal
  double probe_force_n = 0.1;                    ///< total force of one push
  double probe_patch_radius_m = 0.012;           ///< surface nodes within this of the point share it
  int needle_forces = 6;                         ///< forces at sampled interior nodes, in a sampled direction
  double needle_force_n = 0.05;
  double needle_radius_m = 0.004;  ///< free nodes within this of the node share it (a tip)
  int diaphragm_moves = 4;         ///< prescribed displacements (scenes with prescribed nodes)
  double diaphragm_amplitude_m = 0.005;
};

/// Which set to draw: the training loads, or held-out loads at other points, directions and
/// magnitudes (drawn from the same seed after the training draws, so never the same ones).
enum class LoadSet { training, held_out };

/// Push, needle and diaphragm loads are applied on top of the scene's gravity. Held-out sets
/// have about half as many loads of each kind as the training set.
std::vector<TrainingLoad> make_training_loads(const TetMesh& mesh, const TissueScene& scene,
                                              const TrainingLoadOptions& options, LoadSet set);

/// `base` with a diaphragm: the boundary nodes within `radius_m` of the boundary node highest
/// against gravity among those at least 2 radius_m from every fixed node become prescribed
/// nodes (none if there is no such node).
TissueScene with_diaphragm(const TetMesh& mesh, TissueScene base, double radius_m);

/// How each load is solved to equilibrium with the full-order model.
struct StaticSolveOptions {
  TissueSolverOptions solver = default_solver();
  /// The load grows linearly over these quasi-static steps; a solve that inverts elements or
  /// does not converge is tried again with a ramp 4 and 16 times longer.
  int ramp_steps = 20;
  int max_steps = 300;  ///< after the ramp's end: more is an Error (no convergence)
  /// The load fractions whose equilibria are kept, ascending, ending at 1 (the solve goes
  /// from one to the next): the half load samples the non-linear path for POD.
  std::vector<double> snapshot_fractions{0.5, 1.0};
  double converged_step_m = 1e-6;  ///< done when no node moved more than this in a step
  /// Loads solved at once, each on a thread of its own (1: all on the caller's). Every load
  /// is solved from rest on data of its own, so the snapshots do not depend on it.
  int threads = 1;

  /// Corotational, quasi-static, LDL^T-warped, 3 CG iterations, Rayleigh mass 10/s (relaxes
  /// each Newton step without moving the equilibrium).
  static TissueSolverOptions default_solver();
};

/// Displacement snapshots from rest, column-major (3 n) x count, in metres: for each load,
/// one per StaticSolveOptions::snapshot_fractions, in that order.
struct Snapshots {
  std::vector<double> displacements_m;
  int count = 0;
  int total_steps = 0;  ///< quasi-static steps taken over all loads
};

/// One load's equilibria: 3 n displacements (metres) per StaticSolveOptions::snapshot_fractions,
/// in that order, and the quasi-static steps they took.
struct LoadSnapshots {
  std::vector<double> displacements_m;
  int count = 0;  ///< snapshots: one per fraction
  int steps = 0;
};

/// Solves every load on its own (one model per distinct gravity vector, options.threads loads
/// at a time): for each load, in order, its snapshots or the Error that names it (no
/// convergence, inverted elements, or what the model refused).
std::vector<Result<LoadSnapshots>> solve_each_static_load(const TetMesh& mesh, const TissueScene& scene,
                                                          std::span<const TrainingLoad> loads,
                                                          const StaticSolveOptions& options = {});

/// `load`'s snapshots appended to `snapshots`.
void append_snapshots(Snapshots& snapshots, const LoadSnapshots& load);

/// Solves every load, as solve_each_static_load. Errors: the first load's, in order, that
/// did not solve.
Result<Snapshots> solve_static_loads(const TetMesh& mesh, const TissueScene& scene, std::span<const TrainingLoad> loads,
                                     const StaticSolveOptions& options = {});

/// How a reduced model is brought to static equilibrium under one load.
struct ReducedStaticOptions {
  int ramp_steps = 20;             ///< quasi-static reduced steps over which the load grows
  int max_steps = 400;             ///< after the ramp's end
  double converged_step_m = 1e-7;  ///< done when no reconstructed node moved more in a step
  int newton_iterations = 2;       ///< per step, on the current tangent (not frozen)
  /// Rayleigh mass damping of the steps, as the full order's.
  double relaxation_per_s = StaticSolveOptions::default_solver().rayleigh_mass_per_s;
};

/// Static displacements from rest (3 n, metres) of `load` with the reduced model of `basis`
/// (built on scene_for_load(scene, load) with reduction_solver_options(basis.force_kind)),
/// and, with `last_step`, the report of its last step. Errors: the model's own, or no
/// convergence (naming the load).
Result<std::vector<double>> solve_reduced_static(const TetMesh& mesh, const TissueScene& scene,
                                                 const ReducedBasis& basis, const TrainingLoad& load,
                                                 const ReducedStaticOptions& options = {},
                                                 ReducedStepReport* last_step = nullptr);

/// Nodal displacement errors of `u_m` against `reference_m` (both 3 n): the RMS and largest
/// nodal error, and the error at `target_node`, in metres, and the reference's largest
/// nodal displacement.
struct DisplacementError {
  double rms_m = 0.0, max_m = 0.0, target_m = 0.0, reference_max_m = 0.0;
};
DisplacementError displacement_error(std::span<const double> u_m, std::span<const double> reference_m,
                                     std::int32_t target_node);

/// The interior node nearest the centroid of the mesh's volume: the target point of meshes
/// without a tumour region (liverFine), deep in the organ, where a needle aims.
std::int32_t central_target_node(const TetMesh& mesh);

/// `scene` with the gravity of `load`.
TissueScene scene_for_load(const TissueScene& scene, const TrainingLoad& load);

/// Radius of the diaphragm patch of liver_reduction_scene, in metres.
inline constexpr double kLiverDiaphragmRadiusM = 0.01;

/// The scene the reduced livers are trained and run on: liver_scenes()'s gravity scene (held
/// in the anchor's box, gravity along -y) with a diaphragm (with_diaphragm, radius
/// kLiverDiaphragmRadiusM, at the top of the liver).
TissueScene liver_reduction_scene(const TetMesh& mesh);

/// The full-order element law of a reduced force kind (what make_modal_basis, make_pod_basis,
/// add_force_reduction and make_reduced_model are given): St Venant-Kirchhoff for the StVK
/// kinds, corotational linear elasticity for corotational_cubature, linear for linear.
TissueSolverOptions reduction_solver_options(ReducedForceKind kind);

}  // namespace nav
