#pragma once
// Non-negative least squares (Lawson and Hanson's active-set method), for the ECSW weights
// of the reduced-force cubature. Init time; internal to rtlib/nav/reduced.
#include <Eigen/Dense>

namespace nav::detail {

/// What nnls found.
struct NnlsResult {
  Eigen::VectorXd x;       ///< argmin |A x - b| subject to x >= 0
  int iterations = 0;      ///< outer iterations taken
  bool converged = false;  ///< the KKT conditions hold to the tolerance
};

/// Solves min |A x - b| with x >= 0 by at most max_iterations outer iterations (3 columns(A) if
/// not positive). Columns of A are expected to be of comparable scale. `start` (empty: zero)
/// warm-starts it with the solution of the same problem on A's first start.size() columns:
/// its positive entries, the least-squares solution on their columns, are where it begins
/// (one outer iteration for each column that enters, instead of one for each column used).
NnlsResult nnls(const Eigen::MatrixXd& a, const Eigen::VectorXd& b, const Eigen::VectorXd& start = {},
                int max_iterations = 0);

}  // namespace nav::detail
