#pragma once
// Offline reduction of a tissue scene (init time: allocates, returns Result/Status): the
// vibration-mode and POD subspaces, and the hyper-reduction of their internal forces. What
// navtool reduce runs, and what the reduced-model artifact stores.
#include <span>

#include "nav/core/error.hpp"
#include "nav/mesh/tet_mesh.hpp"
#include "nav/reduced/reduced_basis.hpp"
#include "nav/tissue/tissue_scene.hpp"

namespace nav {

/// Settings of the offline reduction.
struct ReductionOptions {
  ReducedBasisSource source = ReducedBasisSource::pod;
  ReducedForceKind force_kind = ReducedForceKind::corotational_cubature;
  int basis_size = 16;                        ///< r
  int max_cubature_samples = 64;              ///< m: most tetrahedra ECSW may select
  double cubature_relative_tolerance = 0.01;  ///< ECSW stops once the training force error is below this
};

/// Vibration modes K phi = w^2 M phi (lumped M, K the rest stiffness plus the frame springs)
/// with the fixed and prescribed nodes removed, by shift-invert Lanczos (Spectra) on a sparse
/// LDL^T; M-orthonormal columns, w^2 in column_values. With source modal_derivatives the
/// first modes are completed by their St Venant-Kirchhoff modal derivatives up to basis_size.
/// Fills diaphragm_lift when the scene prescribes nodes.
Result<ReducedBasis> make_modal_basis(const TetMesh& mesh, const TissueScene& scene, const TissueSolverOptions& solver,
                                      const ReductionOptions& options);

/// Mass-weighted POD (method of snapshots) of displacement snapshots (column-major
/// 3 node_count x snapshot_count, metres from rest): the leading basis_size M-orthonormal
/// directions, the cumulative captured energy fraction per mode in column_values. The
/// diaphragm lift's part of each snapshot is taken out first.
Result<ReducedBasis> make_pod_basis(const TetMesh& mesh, const TissueScene& scene, const TissueSolverOptions& solver,
                                    const ReductionOptions& options, std::span<const double> snapshots_m,
                                    int snapshot_count);

/// Fills the force reduction of basis.force_kind from training snapshots (as for
/// make_pod_basis): ECSW sample tetrahedra and non-negative weights for the cubature kinds,
/// the cubic polynomial's coefficients for stvk_cubic_polynomial, nothing more for linear;
/// and, for every kind, training_q_bound and training_residual_bound (the largest relative
/// error of the reduced internal force against the full projection on the snapshots).
Status add_force_reduction(const TetMesh& mesh, const TissueScene& scene, const TissueSolverOptions& solver,
                           const ReductionOptions& options, std::span<const double> snapshots_m, int snapshot_count,
                           ReducedBasis& basis);

}  // namespace nav
