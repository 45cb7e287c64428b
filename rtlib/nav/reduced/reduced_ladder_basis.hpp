#pragma once
// The basis of the rung above another on a reduced ladder (init time: allocates, returns
// Result): the lower rung's columns kept first, so that the transfer between the two rungs is
// exact, completed by the leading POD directions of training snapshots that the lower basis
// does not represent (typically snapshots of loads beyond the lower rung's training).
#include <span>

#include "nav/core/error.hpp"
#include "nav/mesh/tet_mesh.hpp"
#include "nav/reduced/reduced_basis.hpp"
#include "nav/tissue/tissue_scene.hpp"

namespace nav {

/// `lower`'s columns, then the mass-weighted POD of the snapshots' part M-orthogonal to them
/// (snapshots as for make_pod_basis), up to basis_size columns in all. The new columns'
/// column_values are the cumulative fraction of that part's energy they capture. The force
/// reduction and training envelope are left to add_force_reduction (none is copied). Errors
/// name the field: a basis of another mesh, a size not above lower's, snapshots adding too
/// few directions.
Result<ReducedBasis> extend_basis(const TetMesh& mesh, const TissueScene& scene, const TissueSolverOptions& solver,
                                  const ReducedBasis& lower, int basis_size, std::span<const double> snapshots_m,
                                  int snapshot_count);

}  // namespace nav
