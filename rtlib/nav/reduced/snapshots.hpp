#pragma once
// Training snapshots as the reduction reads them (init time, internal to rtlib/nav/reduced).
#include <Eigen/Dense>
#include <span>
#include <vector>

#include "nav/reduced/full_system.hpp"

namespace nav::detail {

/// The free-dof parts (columns) of `snapshot_count` snapshots of 3 node_count displacements
/// (column-major), less the diaphragm lift's response to each one's prescribed displacement.
/// Errors on a size mismatch or a non-finite value.
Result<Eigen::MatrixXd> free_snapshots(const FullSystem& system, const std::vector<double>& lift,
                                       std::span<const double> snapshots_m, int snapshot_count);

/// lift (3 node_count x 3, column-major) times d, added to `out` (3 node_count). Nothing when the lift is empty.
void add_lift(const std::vector<double>& lift, const Eigen::Vector3d& d, Eigen::VectorXd& out);

}  // namespace nav::detail
