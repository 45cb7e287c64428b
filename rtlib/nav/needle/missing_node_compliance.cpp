#include "nav/needle/missing_node_compliance.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>

#include "nav/tissue/tet_fem_model.hpp"

namespace nav {
namespace {

using RowMatrix3 = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>;
using FactorRows = Eigen::Map<const Eigen::Matrix<double, 3, Eigen::Dynamic, Eigen::RowMajor>>;

/// Wendland's C2 function of s = distance / support radius, zero from s = 1.
double wendland_taper(double s) {
  if (s >= 1.0) return 0.0;
  const double t = 1.0 - s;
  return t * t * t * t * (4.0 * s + 1.0);
}

/// `c` symmetrised, its negative eigenvalues dropped.
Eigen::Matrix3d positive_part(const Eigen::Matrix3d& c) {
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(0.5 * (c + c.transpose()));
  const Eigen::Vector3d kept = eigen.eigenvalues().cwiseMax(0.0);
  return eigen.eigenvectors() * kept.asDiagonal() * eigen.eigenvectors().transpose();
}

}  // namespace

Result<NodePairCompliance> missing_node_compliance(const ReducedComplianceFactors& reduced, const TetFemModel& full,
                                                   double radius_m) {
  const int rank = reduced.rank;
  if (rank < 1) return Error{.message = "has no low-rank tissue compliance", .field = "reduced.rank"};
  const auto nodes = static_cast<std::size_t>(full.node_count());
  if (reduced.factors.size() != 3 * nodes * static_cast<std::size_t>(rank))
    return Error{.message = "is on another mesh than the reduced tissue", .field = "full"};
  if (!has_rest_step_response(full))
    return Error{.message = "keeps no rest factor (solver ldlt_warped, an implicit or quasi-static step)",
                 .field = "full"};
  if (!(radius_m >= 0.0 && std::isfinite(radius_m)))
    return Error{.message = "must be a distance of zero or more", .field = "radius_m"};
  const std::span<const double> rest = full.rest_positions_m();
  const auto position = [&](std::size_t n) { return Eigen::Map<const Eigen::Vector3d>(rest.data() + 3 * n); };
  const auto factors = [&](std::size_t n) {
    return FactorRows(reduced.factors.data() + 3 * n * static_cast<std::size_t>(rank), 3, rank);
  };
  NodePairCompliance table;
  table.starts.assign(1, 0);
  std::vector<double> response(3 * nodes * 3), work(2 * static_cast<std::size_t>(full.free_dof_count()));
  for (std::size_t a = 0; a < nodes; ++a) {
    bool free = true;
    for (int axis = 0; axis < 3 && free; ++axis)
      free = rest_step_response_m(
          full, static_cast<std::int32_t>(a), axis,
          std::span<double>(response).subspan(3 * nodes * static_cast<std::size_t>(axis), 3 * nodes), work);
    for (std::size_t b = 0; b < nodes && free; ++b) {
      const double distance_m = (position(b) - position(a)).norm();
      if (b != a && !(distance_m < radius_m)) continue;
      // Column j: b's displacement under a force along j on a, C(b, a); the table's block (a, b)
      // is C(a, b) = C(b, a)^T.
      Eigen::Matrix3d b_from_a;
      for (std::size_t j = 0; j < 3; ++j)
        b_from_a.col(static_cast<Eigen::Index>(j)) =
            Eigen::Map<const Eigen::Vector3d>(response.data() + 3 * nodes * j + 3 * b);
      if (b_from_a.isZero(0.0)) continue;  // a node `full` holds
      Eigen::Matrix3d missed = b_from_a.transpose() - factors(a) * factors(b).transpose();
      missed = b == a ? positive_part(missed) : Eigen::Matrix3d(wendland_taper(distance_m / radius_m) * missed);
      table.nodes.push_back(static_cast<std::int32_t>(b));
      const RowMatrix3 row_major = missed;
      table.blocks_m_per_n.insert(table.blocks_m_per_n.end(), row_major.data(), row_major.data() + 9);
    }
    table.starts.push_back(static_cast<std::int32_t>(table.nodes.size()));
  }
  return table;
}

Result<NodePairCompliance> static_missing_node_compliance(const ReducedModel& liver, const TetFemModel& full,
                                                          double radius_m) {
  ReducedSolverOptions at_rest = liver.options();
  at_rest.integrator = ReducedIntegrator::quasi_static;
  at_rest.newton_iterations = 1;
  at_rest.frozen_tangent = true;
  at_rest.rayleigh_mass_per_s = at_rest.rayleigh_stiffness_s = 0.0;
  auto twin = with_solver_options(liver, at_rest);
  if (!twin.ok()) return twin.error();
  auto factors = reduced_compliance_factors(twin.value(), kComplianceProbeForceN);
  if (!factors.ok()) return factors.error();
  return missing_node_compliance(factors.value(), full, radius_m);
}

}  // namespace nav
