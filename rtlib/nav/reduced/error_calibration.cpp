#include "nav/reduced/error_calibration.hpp"

#include <Eigen/Dense>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <string>
#include <system_error>
#include <thread>

#include "nav/reduced/full_system.hpp"
#include "nav/reduced/packed_compliance.hpp"

namespace nav {
namespace {

/// What every free node's missing compliance is computed from (see missing_patch_compliance).
struct PatchProblem {
  const TetMesh& mesh;
  const std::vector<std::int32_t>& free_nodes;
  const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>>& factor;
  const Eigen::MatrixXd& free_basis;   ///< U: the basis rows of the free nodes, in their order
  const Eigen::MatrixXd& flexibility;  ///< (U^T (K + Ks) U)^-1
  double radius_m;
};

/// Writes the missing compliance of the free nodes first, first + stride, ... into `out` (one
/// thread's share: every node's values depend on nothing but the problem).
void fill_missing_compliance(const PatchProblem& p, std::size_t first, std::size_t stride, std::vector<double>& out) {
  const Eigen::Index unknowns = p.free_basis.rows();
  const Eigen::Index r = p.free_basis.cols();
  Eigen::VectorXd load = Eigen::VectorXd::Zero(unknowns);
  Eigen::Matrix<double, Eigen::Dynamic, 3> forward(unknowns, 3);
  const Eigen::VectorXd inverse_d = p.factor.vectorD().cwiseInverse();
  std::vector<Eigen::Index> patch;
  for (std::size_t i = first; i < p.free_nodes.size(); i += stride) {
    const Point3& centre = p.mesh.nodes_m[static_cast<std::size_t>(p.free_nodes[i])];
    patch.clear();
    for (std::size_t j = 0; j < p.free_nodes.size(); ++j) {
      const Point3& q = p.mesh.nodes_m[static_cast<std::size_t>(p.free_nodes[j])];
      const double d2 = (q[0] - centre[0]) * (q[0] - centre[0]) + (q[1] - centre[1]) * (q[1] - centre[1]) +
                        (q[2] - centre[2]) * (q[2] - centre[2]);
      if (d2 <= p.radius_m * p.radius_m) patch.push_back(3 * static_cast<Eigen::Index>(j));
    }
    const double weight = 1.0 / static_cast<double>(patch.size());
    Eigen::Matrix<double, 3, Eigen::Dynamic> mean_rows = Eigen::Matrix<double, 3, Eigen::Dynamic>::Zero(3, r);
    for (const Eigen::Index at : patch) mean_rows += weight * p.free_basis.middleRows<3>(at);
    for (int c = 0; c < 3; ++c) {
      for (const Eigen::Index at : patch) load[at + c] = weight;
      forward.col(c) = p.factor.permutationP() * load;
      for (const Eigen::Index at : patch) load[at + c] = 0.0;
    }
    p.factor.matrixL().solveInPlace(forward);
    Eigen::Matrix3d missed = forward.transpose() * inverse_d.asDiagonal() * forward;
    missed -= mean_rows * p.flexibility * mean_rows.transpose();
    missed = 0.5 * (missed + missed.transpose()).eval();
    pack_compliance(missed, out.data() + 6 * static_cast<std::size_t>(p.free_nodes[i]));
  }
}

/// The static compliance the basis misses about every node, 6 values per node (see
/// ReducedErrorCalibration): a unit force spread evenly over the free nodes within the patch
/// radius, its full-order response averaged over the same nodes, less the basis's own,
/// W_n (U^T (K + Ks) U)^-1 W_n^T with W_n the patch's mean basis rows. The full order's is
/// the quadratic form b_c^T (K + Ks)^-1 b_d of the patch's loads b, with the rest factor
/// P (K + Ks) P^T = L D L^T: y_c^T D^-1 y_d with y = L^-1 P b, 3 forward solves per free node
/// (a forward solve skips the columns where y is still zero: most of them, for a patch), the
/// nodes shared out over `threads`.
Result<std::vector<double>> missing_patch_compliance(const TetMesh& mesh, const TissueScene& scene,
                                                     const ReducedBasis& basis, double radius_m, int threads) {
  auto system = detail::make_full_system(mesh, scene, reduction_solver_options(basis.force_kind));
  if (!system.ok()) return system.error();
  const detail::TetFemTables& tables = system.value().model.tables();
  const Eigen::SparseMatrix<double>& stiffness = system.value().stiffness;
  const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> factor(stiffness);
  if (factor.info() != Eigen::Success)
    return Error{.message = "the full-order stiffness with the supports applied is singular", .field = "scene"};
  const int r = basis.basis_size;
  const Eigen::Map<const Eigen::MatrixXd> all(basis.basis.data(), 3 * static_cast<Eigen::Index>(mesh.nodes_m.size()),
                                              r);
  Eigen::MatrixXd u(stiffness.rows(), r);
  for (std::size_t i = 0; i < tables.free_nodes.size(); ++i)
    u.middleRows<3>(3 * static_cast<Eigen::Index>(i)) = all.middleRows<3>(3 * tables.free_nodes[i]);
  const Eigen::MatrixXd flexibility = (u.transpose() * (stiffness * u)).ldlt().solve(Eigen::MatrixXd::Identity(r, r));
  std::vector<double> out(6 * mesh.nodes_m.size(), 0.0);
  const PatchProblem problem{mesh, tables.free_nodes, factor, u, flexibility, radius_m};
  const auto shares = static_cast<std::size_t>(std::max(threads, 1));
  std::vector<std::string> failures(shares);
  const auto fill_share = [&](std::size_t share) noexcept {
    try {
      fill_missing_compliance(problem, share, shares, out);
    } catch (const std::exception& e) {
      failures[share] = e.what();
    }
  };
  std::vector<std::thread> helpers;
  std::size_t share = 1;
  for (; share < shares; ++share) {
    try {
      helpers.emplace_back(fill_share, share);
    } catch (const std::system_error&) {
      break;  // no more threads to be had: the caller takes the remaining shares
    }
  }
  for (std::size_t own = share; own < shares; ++own) fill_share(own);
  fill_share(0);
  for (std::thread& helper : helpers) helper.join();
  for (const std::string& failure : failures)
    if (!failure.empty()) return Error{.message = "missing compliance: " + failure, .field = "basis"};
  return out;
}

}  // namespace

double pearson_correlation(std::span<const double> a, std::span<const double> b) {
  const auto n = static_cast<double>(a.size());
  double mean_a = 0.0, mean_b = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k) mean_a += a[k] / n, mean_b += b[k] / n;
  double ab = 0.0, aa = 0.0, bb = 0.0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    ab += (a[k] - mean_a) * (b[k] - mean_b);
    aa += (a[k] - mean_a) * (a[k] - mean_a);
    bb += (b[k] - mean_b) * (b[k] - mean_b);
  }
  return aa > 0.0 && bb > 0.0 ? ab / std::sqrt(aa * bb) : 0.0;
}

Result<ErrorCalibrationReport> calibrate_error_estimate(const TetMesh& mesh, const TissueScene& scene,
                                                        std::span<const TrainingLoad> loads,
                                                        std::span<const std::vector<double>> full_order_m,
                                                        ReducedBasis& basis, const ErrorCalibrationOptions& options) {
  if (full_order_m.size() != loads.size())
    return Error{.message = "one full-order solution per load is needed", .field = "full_order_m"};
  auto compliance = missing_patch_compliance(mesh, scene, basis, options.patch_radius_m, options.threads);
  if (!compliance.ok()) return compliance.error();
  ReducedErrorCalibration& c = basis.error_calibration;
  c = {};
  c.missing_compliance_m_per_n = std::move(compliance).value();
  c.gain = 1.0;  // the step's estimate is the missed displacement while calibrating
  ErrorCalibrationReport report;
  double log_ratio_sum = 0.0;
  for (std::size_t k = 0; k < loads.size(); ++k) {
    if (full_order_m[k].size() != 3 * mesh.nodes_m.size())
      return Error{.message = "is not 3 values per node", .field = "full_order_m[" + std::to_string(k) + "]"};
    ReducedStepReport last;
    auto reduced = solve_reduced_static(mesh, scene, basis, loads[k], options.reduced_static, &last);
    if (!reduced.ok()) {
      report.unsolved.push_back(reduced.error());
      continue;
    }
    const double true_error_m = displacement_error(reduced.value(), full_order_m[k], -1).max_m;
    report.loads.push_back({loads[k].name, true_error_m, last.estimated_error_m, 0.0});
    if (true_error_m > 0.0 && last.estimated_error_m > 0.0)
      log_ratio_sum += std::log(true_error_m / last.estimated_error_m), ++c.held_out_loads;
  }
  if (c.held_out_loads < 3)
    return Error{.message = "fewer than 3 solved held-out loads with point forces and a positive error (" +
                            std::to_string(report.unsolved.size()) + " not solved by the reduced model" +
                            (report.unsolved.empty() ? "" : ", first " + report.unsolved.front().describe()) + ")",
                 .field = "loads"};
  c.gain = std::exp(log_ratio_sum / c.held_out_loads);
  std::vector<double> estimated, truth;
  c.lowest_ratio = 1e300;
  for (HeldOutEstimate& load : report.loads) {
    load.estimated_error_m = c.gain * load.missed_m;
    if (!(load.true_error_m > 0.0 && load.missed_m > 0.0)) continue;
    estimated.push_back(load.estimated_error_m);
    truth.push_back(load.true_error_m);
    c.lowest_ratio = std::min(c.lowest_ratio, load.true_error_m / load.estimated_error_m);
    c.highest_ratio = std::max(c.highest_ratio, load.true_error_m / load.estimated_error_m);
  }
  c.correlation = pearson_correlation(estimated, truth);
  return report;
}

}  // namespace nav
