// Nested bases for the rungs of a reduced ladder.
#include "nav/reduced/reduced_ladder_basis.hpp"

#include <algorithm>
#include <string>

#include "nav/reduced/basis_tools.hpp"
#include "nav/reduced/snapshots.hpp"

namespace nav {

Result<ReducedBasis> extend_basis(const TetMesh& mesh, const TissueScene& scene, const TissueSolverOptions& solver,
                                  const ReducedBasis& lower, int basis_size, std::span<const double> snapshots_m,
                                  int snapshot_count) {
  const auto n3 = 3 * mesh.nodes_m.size();
  if (lower.mesh_fingerprint != mesh_fingerprint(mesh))
    return Error{.message = "the basis belongs to another mesh", .field = "mesh_fingerprint"};
  if (lower.basis_size < 1 || lower.basis.size() != n3 * static_cast<std::size_t>(lower.basis_size))
    return Error{.message = "the basis is not 3 node_count x basis_size", .field = "basis"};
  if (basis_size <= lower.basis_size)
    return Error{.message = "the extended basis must have more than " + std::to_string(lower.basis_size) + " columns",
                 .field = "basis_size"};
  auto system = detail::make_full_system(mesh, scene, solver);
  if (!system.ok()) return system.error();
  const detail::TetFemTables& tables = system.value().model.tables();
  auto lift = detail::diaphragm_lift(system.value());
  if (!lift.ok()) return lift.error();
  auto snapshots = detail::free_snapshots(system.value(), lift.value(), snapshots_m, snapshot_count);
  if (!snapshots.ok()) return snapshots.error();
  const Eigen::VectorXd& mass = system.value().mass_kg;
  const Eigen::Index r = lower.basis_size;
  Eigen::MatrixXd kept(mass.size(), r);
  for (Eigen::Index j = 0; j < r; ++j)
    kept.col(j) = detail::restrict_free(
        tables, std::span<const double>(lower.basis).subspan(static_cast<std::size_t>(j) * n3, n3));
  // The snapshots' part the lower basis misses, and its POD (method of snapshots).
  const Eigen::MatrixXd missed = snapshots.value() - kept * (kept.transpose() * mass.asDiagonal() * snapshots.value());
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(missed.transpose() * mass.asDiagonal() * missed);
  if (eigen.info() != Eigen::Success)
    return Error{.message = "the snapshot correlation has no eigen decomposition", .field = "snapshots_m"};
  const Eigen::Index count = missed.cols();
  Eigen::MatrixXd candidates(mass.size(), r + count);
  candidates.leftCols(r) = kept;
  for (Eigen::Index k = 0; k < count; ++k) candidates.col(r + k) = missed * eigen.eigenvectors().col(count - 1 - k);
  constexpr double kDropFraction = 1e-6;  // what is left of a direction after removing the kept ones
  Eigen::MatrixXd columns = detail::mass_orthonormalize(candidates, mass, kDropFraction, basis_size);
  if (columns.cols() < basis_size)
    return Error{.message = "the snapshots add only " + std::to_string(columns.cols() - r) + " directions to the basis",
                 .field = "basis_size"};
  columns.leftCols(r) = kept;  // the lower rung's columns exactly (Gram-Schmidt changed them by rounding only)
  auto basis = detail::pack_basis(mesh, system.value(), columns, lower.source, lower.force_kind);
  if (!basis.ok()) return basis;
  std::copy_n(lower.column_values.begin(), std::min(lower.column_values.size(), static_cast<std::size_t>(r)),
              basis.value().column_values.begin());
  const double total = std::max(eigen.eigenvalues().cwiseMax(0.0).sum(), 1e-300);
  double captured = 0.0;
  for (Eigen::Index k = 0; k + r < basis_size; ++k) {
    captured += std::max(0.0, eigen.eigenvalues()[count - 1 - k]);
    basis.value().column_values[static_cast<std::size_t>(r + k)] = captured / total;
  }
  return basis;
}

}  // namespace nav
