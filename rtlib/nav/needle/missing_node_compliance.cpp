#include "nav/needle/missing_node_compliance.hpp"

#include <Eigen/Eigenvalues>

#include "nav/reduced/packed_compliance.hpp"
#include "nav/tissue/tet_fem_model.hpp"

namespace nav {

Result<std::vector<double>> missing_node_compliance(const NeedleTissueModel& coupled, const TetFemModel& full) {
  const int rank = coupled.compliance_rank;
  if (rank < 1) return Error{.message = "has no low-rank tissue compliance", .field = "coupled.compliance_rank"};
  const auto nodes = static_cast<std::size_t>(full.node_count());
  if (coupled.compliance_factors.size() != 3 * nodes * static_cast<std::size_t>(rank))
    return Error{.message = "is on another mesh than the coupled tissue", .field = "full"};
  if (!has_rest_step_response(full))
    return Error{.message = "keeps no rest factor (solver ldlt_warped, an implicit or quasi-static step)",
                 .field = "full"};
  std::vector<double> out(6 * nodes, 0.0), response(3 * nodes),
      work(2 * static_cast<std::size_t>(full.free_dof_count()));
  for (std::size_t n = 0; n < nodes; ++n) {
    Eigen::Matrix3d missed;
    bool free = true;
    for (int axis = 0; axis < 3 && free; ++axis) {
      free = rest_step_response_m(full, static_cast<std::int32_t>(n), axis, response, work);
      missed.col(axis) = Eigen::Vector3d(response[3 * n], response[3 * n + 1], response[3 * n + 2]);
    }
    if (!free) continue;
    const Eigen::Map<const Eigen::Matrix<double, 3, Eigen::Dynamic, Eigen::RowMajor>> v(
        coupled.compliance_factors.data() + 3 * n * static_cast<std::size_t>(rank), 3, rank);
    missed -= v * v.transpose();
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(0.5 * (missed + missed.transpose()));
    const Eigen::Vector3d kept = eigen.eigenvalues().cwiseMax(0.0);
    missed = eigen.eigenvectors() * kept.asDiagonal() * eigen.eigenvectors().transpose();
    pack_compliance(missed, out.data() + 6 * n);
  }
  return out;
}

}  // namespace nav
