#include "nav/reduced/nnls.hpp"

#include <algorithm>
#include <limits>
#include <vector>

namespace nav::detail {
namespace {

/// Least squares on the columns of `a` in `passive` (others zero), by column-pivoted QR.
Eigen::VectorXd passive_solve(const Eigen::MatrixXd& a, const Eigen::VectorXd& b, const std::vector<bool>& passive) {
  std::vector<Eigen::Index> columns;
  for (Eigen::Index j = 0; j < a.cols(); ++j)
    if (passive[static_cast<std::size_t>(j)]) columns.push_back(j);
  Eigen::MatrixXd sub(a.rows(), static_cast<Eigen::Index>(columns.size()));
  for (std::size_t k = 0; k < columns.size(); ++k) sub.col(static_cast<Eigen::Index>(k)) = a.col(columns[k]);
  const Eigen::VectorXd solution = sub.colPivHouseholderQr().solve(b);
  Eigen::VectorXd z = Eigen::VectorXd::Zero(a.cols());
  for (std::size_t k = 0; k < columns.size(); ++k) z[columns[k]] = solution[static_cast<Eigen::Index>(k)];
  return z;
}

}  // namespace

NnlsResult nnls(const Eigen::MatrixXd& a, const Eigen::VectorXd& b, const Eigen::VectorXd& start, int max_iterations) {
  const Eigen::Index n = a.cols();
  if (max_iterations <= 0) max_iterations = 3 * static_cast<int>(n) + 10;
  NnlsResult result{Eigen::VectorXd::Zero(n), 0, false};
  std::vector<bool> passive(static_cast<std::size_t>(n), false);
  for (Eigen::Index j = 0; j < std::min(n, start.size()); ++j)
    if (start[j] > 0.0) {
      result.x[j] = start[j];
      passive[static_cast<std::size_t>(j)] = true;
    }
  const double tolerance = 10.0 * std::numeric_limits<double>::epsilon() * a.cwiseAbs().maxCoeff() *
                           static_cast<double>(std::max(a.rows(), n)) * std::max(1.0, b.cwiseAbs().maxCoeff());
  Eigen::VectorXd& x = result.x;
  for (; result.iterations < max_iterations; ++result.iterations) {
    const Eigen::VectorXd gradient = a.transpose() * (b - a * x);
    Eigen::Index best = -1;
    double best_value = tolerance;
    for (Eigen::Index j = 0; j < n; ++j)
      if (!passive[static_cast<std::size_t>(j)] && gradient[j] > best_value) {
        best_value = gradient[j];
        best = j;
      }
    if (best < 0) {
      result.converged = true;
      return result;
    }
    passive[static_cast<std::size_t>(best)] = true;
    for (int inner = 0; inner < 3 * static_cast<int>(n) + 10; ++inner) {
      const Eigen::VectorXd z = passive_solve(a, b, passive);
      bool feasible = true;
      for (Eigen::Index j = 0; j < n; ++j) feasible = feasible && (!passive[static_cast<std::size_t>(j)] || z[j] > 0.0);
      if (feasible) {
        x = z;
        break;
      }
      double alpha = 1.0;  // step from x towards z until a passive variable reaches zero
      for (Eigen::Index j = 0; j < n; ++j)
        if (passive[static_cast<std::size_t>(j)] && z[j] <= 0.0) alpha = std::min(alpha, x[j] / (x[j] - z[j]));
      x += alpha * (z - x);
      for (Eigen::Index j = 0; j < n; ++j)
        if (passive[static_cast<std::size_t>(j)] && x[j] <= tolerance) {
          passive[static_cast<std::size_t>(j)] = false;
          x[j] = 0.0;
        }
    }
  }
  return result;
}

}  // namespace nav::detail
