// Moving a reduced Kalman filter's correction and covariance between two bases of one liver,
// as an escalation ladder changes rung.
#include <Eigen/Core>
#include <algorithm>

#include "nav/fusion/reduced_kalman.hpp"

namespace nav {
namespace {

std::size_t index_at(int i) { return static_cast<std::size_t>(i); }

}  // namespace

void carry_filter(const ReducedKalmanModel& from_model, const ReducedKalmanData& from,
                  const ReducedKalmanModel& to_model, ReducedKalmanData& to, std::span<const double> a,
                  std::span<const double> added, std::span<double> workspace) noexcept {
  const int n = from_model.r, m = to_model.r;
  // dq' = A dq; the product A P (m x n) goes to the workspace, then A P A^T (+ added).
  for (int i = 0; i < m; ++i) {
    double sum = 0.0;
    for (int j = 0; j < n; ++j) sum += a[index_at(i * n + j)] * from.correction[index_at(j)];
    to.correction[index_at(i)] = sum;
  }
  for (int i = 0; i < m; ++i)
    for (int k = 0; k < n; ++k) {
      double sum = 0.0;
      for (int j = 0; j < n; ++j) sum += a[index_at(i * n + j)] * from.covariance[index_at(j * n + k)];
      workspace[index_at(i * n + k)] = sum;
    }
  for (int i = 0; i < m; ++i)
    for (int l = 0; l < m; ++l) {
      double sum = added.empty() ? 0.0 : added[index_at(i * m + l)];
      for (int k = 0; k < n; ++k) sum += workspace[index_at(i * n + k)] * a[index_at(l * n + k)];
      to.covariance[index_at(i * m + l)] = sum;
    }
  for (int i = 0; i < m; ++i)  // exactly symmetric, as the filter keeps it
    for (int l = 0; l < i; ++l) {
      const double mean = 0.5 * (to.covariance[index_at(i * m + l)] + to.covariance[index_at(l * m + i)]);
      to.covariance[index_at(i * m + l)] = mean;
      to.covariance[index_at(l * m + i)] = mean;
    }
  to.last_update_ns = from.last_update_ns;
  to.accepted_updates = from.accepted_updates;
  to.rejected_updates = from.rejected_updates;
  to.last_mahalanobis_squared = from.last_mahalanobis_squared;
}

std::vector<double> unseen_directions_prior(const ReducedKalmanModel& big, std::span<const double> transfer,
                                            int r_small) {
  using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  const Eigen::Map<const RowMatrix> t(transfer.data(), big.r, r_small);
  const RowMatrix n = RowMatrix::Identity(big.r, big.r) - t * t.transpose();
  const Eigen::Map<const Eigen::VectorXd> prior(big.prior_variance.data(), big.r);
  const RowMatrix added = n * prior.asDiagonal() * n.transpose();
  return {added.data(), added.data() + added.size()};
}

}  // namespace nav
