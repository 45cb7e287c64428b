// Mass-weighted proper orthogonal decomposition of full-order snapshots (method of snapshots).
#include <string>

#include "nav/reduced/basis_tools.hpp"
#include "nav/reduced/reduction.hpp"
#include "nav/reduced/snapshots.hpp"

namespace nav {

Result<ReducedBasis> make_pod_basis(const TetMesh& mesh, const TissueScene& scene, const TissueSolverOptions& solver,
                                    const ReductionOptions& options, std::span<const double> snapshots_m,
                                    int snapshot_count) {
  auto system = detail::make_full_system(mesh, scene, solver);
  if (!system.ok()) return system.error();
  auto lift = detail::diaphragm_lift(system.value());
  if (!lift.ok()) return lift.error();
  auto snapshots = detail::free_snapshots(system.value(), lift.value(), snapshots_m, snapshot_count);
  if (!snapshots.ok()) return snapshots.error();
  const Eigen::MatrixXd& s = snapshots.value();
  if (options.basis_size < 1 || options.basis_size > snapshot_count)
    return Error{.message = "the basis size must be between 1 and the " + std::to_string(snapshot_count) + " snapshots",
                 .field = "basis_size"};
  const Eigen::VectorXd& mass = system.value().mass_kg;
  // Correlation S^T M S: its eigenvectors a give the modes S a / sqrt(lambda).
  const Eigen::MatrixXd correlation = s.transpose() * mass.asDiagonal() * s;
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(correlation);
  if (eigen.info() != Eigen::Success)
    return Error{.message = "the snapshot correlation has no eigen decomposition", .field = "snapshots_m"};
  const Eigen::Index count = correlation.rows();
  const double total = eigen.eigenvalues().cwiseMax(0.0).sum();
  if (!(total > 0.0)) return Error{.message = "every snapshot is zero over the free nodes", .field = "snapshots_m"};
  // Directions of energy below rounding level of the largest are not in the snapshots' span.
  constexpr double kRankTolerance = 1e-12;
  const double largest = eigen.eigenvalues()[count - 1];
  Eigen::Index rank = 0;
  while (rank < count && eigen.eigenvalues()[count - 1 - rank] > kRankTolerance * largest) ++rank;
  Eigen::MatrixXd candidates(s.rows(), rank);
  for (Eigen::Index k = 0; k < rank; ++k) candidates.col(k) = s * eigen.eigenvectors().col(count - 1 - k);
  constexpr double kDropFraction = 1e-10;
  const Eigen::MatrixXd columns = detail::mass_orthonormalize(candidates, mass, kDropFraction, options.basis_size);
  if (columns.cols() < options.basis_size)
    return Error{.message = "the snapshots span only " + std::to_string(columns.cols()) + " directions",
                 .field = "basis_size"};
  auto basis = detail::pack_basis(mesh, system.value(), columns, ReducedBasisSource::pod, options.force_kind);
  if (!basis.ok()) return basis;
  double captured = 0.0;
  for (Eigen::Index k = 0; k < options.basis_size; ++k) {
    captured += std::max(0.0, eigen.eigenvalues()[count - 1 - k]);
    basis.value().column_values[static_cast<std::size_t>(k)] = captured / total;
  }
  return basis;
}

}  // namespace nav
