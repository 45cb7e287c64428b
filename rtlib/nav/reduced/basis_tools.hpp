#pragma once
// Init-time helpers of the basis builders (internal to rtlib/nav/reduced): mass
// orthonormalisation and the packing of free-dof columns into a ReducedBasis.
#include <Eigen/Dense>

#include "nav/reduced/full_system.hpp"
#include "nav/reduced/reduced_basis.hpp"

namespace nav::detail {

/// Columns of `candidates` made M-orthonormal in order by twice-repeated modified
/// Gram-Schmidt (M diagonal, `mass_kg`); a column whose M-norm falls below
/// `drop_fraction` of its original M-norm is dropped. At most `max_columns` are kept.
Eigen::MatrixXd mass_orthonormalize(const Eigen::MatrixXd& candidates, const Eigen::VectorXd& mass_kg,
                                    double drop_fraction, Eigen::Index max_columns);

/// A basis of `system`'s mesh with free-dof columns `columns` (expanded to every node), the
/// diaphragm lift and the mesh fingerprint.
Result<ReducedBasis> pack_basis(const TetMesh& mesh, const FullSystem& system, const Eigen::MatrixXd& columns,
                                ReducedBasisSource source, ReducedForceKind force_kind);

}  // namespace nav::detail
