#include "nav/reduced/snapshots.hpp"

#include <cmath>
#include <string>

namespace nav::detail {

void add_lift(const std::vector<double>& lift, const Eigen::Vector3d& d, Eigen::VectorXd& out) {
  if (lift.empty()) return;
  const Eigen::Index n3 = out.size();
  for (int c = 0; c < 3; ++c) out += d[c] * Eigen::Map<const Eigen::VectorXd>(lift.data() + c * n3, n3);
}

Result<Eigen::MatrixXd> free_snapshots(const FullSystem& system, const std::vector<double>& lift,
                                       std::span<const double> snapshots_m, int snapshot_count) {
  const TetFemTables& tables = system.model.tables();
  const auto n3 = static_cast<std::size_t>(3 * tables.node_count);
  if (snapshot_count < 1 || snapshots_m.size() != n3 * static_cast<std::size_t>(snapshot_count))
    return Error{.message = "expected " + std::to_string(snapshot_count) + " snapshots of " + std::to_string(n3) +
                            " values, got " + std::to_string(snapshots_m.size()) + " values",
                 .field = "snapshots_m"};
  for (std::size_t i = 0; i < snapshots_m.size(); ++i)
    if (!std::isfinite(snapshots_m[i]))
      return Error{.message = "snapshot " + std::to_string(i / n3) + " has a non-finite value", .field = "snapshots_m"};
  Eigen::MatrixXd free(3 * static_cast<Eigen::Index>(tables.free_nodes.size()), snapshot_count);
  for (int k = 0; k < snapshot_count; ++k) {
    const std::span<const double> snapshot = snapshots_m.subspan(n3 * static_cast<std::size_t>(k), n3);
    Eigen::VectorXd u = Eigen::Map<const Eigen::VectorXd>(snapshot.data(), static_cast<Eigen::Index>(n3));
    add_lift(lift, -prescribed_displacement(tables, snapshot), u);
    free.col(k) = restrict_free(tables, std::span<const double>(u.data(), n3));
  }
  return free;
}

}  // namespace nav::detail
