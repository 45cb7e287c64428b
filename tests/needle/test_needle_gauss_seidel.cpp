// Projected Gauss-Seidel against an independent dense reference: small mixed complementarity
// problems (bilateral rows and unilateral rows capped at a force) with a symmetric positive
// definite W, solved exactly by enumerating every active set (free, in contact, at the cap)
// and keeping the one whose forces and gaps satisfy all the laws. With W positive definite
// the solution is unique, so the enumeration is a reference that does not share any code
// with the solver. Rows come in constraint points of up to three, as in the needle scenes.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cstdio>
#include <random>
#include <vector>

#include "nav/needle/gauss_seidel.hpp"

namespace nav {
namespace {

struct Problem {
  std::vector<ConstraintRow> rows;
  Eigen::MatrixXd w;
};

/// m rows in points of three (each point: one unilateral capped row, two bilateral rows, or
/// all unilateral when `all_unilateral`), W = B B^T + c I with a seeded RNG.
Problem random_problem(int points, unsigned seed, bool all_unilateral) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const int m = 3 * points;
  Problem problem;
  Eigen::MatrixXd b(m, m);
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < m; ++j) b(i, j) = unit(rng);
  problem.w = 1e-3 * (b * b.transpose() / m + 0.5 * Eigen::MatrixXd::Identity(m, m));  // m/N, like the scenes
  for (int p = 0; p < points; ++p)
    for (int k = 0; k < 3; ++k) {
      ConstraintRow row;
      row.node = 1 + p;  // rows of one point share node, weight and tissue point
      row.tissue_point_m = Eigen::Vector3d(0.01 * p, 0.0, 0.0);
      row.law = all_unilateral || k == 0 ? RowLaw::unilateral_capped : RowLaw::bilateral;
      row.cap = 0.2 + 0.5 * (unit(rng) + 1.0);
      row.gap_free_m = 2e-3 * unit(rng);
      row.slot = 3 * p + k;
      problem.rows.push_back(row);
    }
  return problem;
}

/// The exact solution by enumeration of the 3^u active sets of the u unilateral rows.
Eigen::VectorXd enumerate_solution(const Problem& problem) {
  const auto m = static_cast<int>(problem.rows.size());
  std::vector<int> unilateral;
  for (int r = 0; r < m; ++r)
    if (problem.rows[static_cast<std::size_t>(r)].law == RowLaw::unilateral_capped) unilateral.push_back(r);
  Eigen::VectorXd gap_free(m);
  for (int r = 0; r < m; ++r) gap_free[r] = problem.rows[static_cast<std::size_t>(r)].gap_free_m;
  int combinations = 1;
  for (std::size_t k = 0; k < unilateral.size(); ++k) combinations *= 3;
  Eigen::VectorXd found;
  int solutions = 0;
  for (int code = 0; code < combinations; ++code) {
    // state: 0 free (force 0), 1 in contact (gap 0), 2 at the cap (force = cap).
    std::vector<int> state(static_cast<std::size_t>(m), 1);
    for (std::size_t k = 0, c = static_cast<std::size_t>(code); k < unilateral.size(); ++k, c /= 3)
      state[static_cast<std::size_t>(unilateral[k])] = static_cast<int>(c % 3);
    Eigen::VectorXd force = Eigen::VectorXd::Zero(m);
    std::vector<int> unknown;
    for (int r = 0; r < m; ++r) {
      if (state[static_cast<std::size_t>(r)] == 1) unknown.push_back(r);
      if (state[static_cast<std::size_t>(r)] == 2) force[r] = problem.rows[static_cast<std::size_t>(r)].cap;
    }
    const Eigen::VectorXd known_gap = gap_free + problem.w * force;
    const auto n = static_cast<int>(unknown.size());
    Eigen::MatrixXd a(n, n);
    Eigen::VectorXd rhs(n);
    for (int i = 0; i < n; ++i) {
      rhs[i] = -known_gap[unknown[static_cast<std::size_t>(i)]];
      for (int j = 0; j < n; ++j)
        a(i, j) = problem.w(unknown[static_cast<std::size_t>(i)], unknown[static_cast<std::size_t>(j)]);
    }
    if (n > 0) {
      const Eigen::VectorXd solved = a.ldlt().solve(rhs);
      for (int i = 0; i < n; ++i) force[unknown[static_cast<std::size_t>(i)]] = solved[i];
    }
    const Eigen::VectorXd gap = gap_free + problem.w * force;
    bool feasible = true;
    const double tol_n = 1e-12, tol_m = 1e-15;
    for (int r = 0; r < m; ++r) {
      const ConstraintRow& row = problem.rows[static_cast<std::size_t>(r)];
      if (row.law != RowLaw::unilateral_capped) continue;
      const int s = state[static_cast<std::size_t>(r)];
      if (s == 0 && gap[r] < -tol_m) feasible = false;
      if (s == 1 && (force[r] < -tol_n || force[r] > row.cap + tol_n)) feasible = false;
      if (s == 2 && gap[r] > tol_m) feasible = false;
    }
    if (feasible) {
      ++solutions;
      found = force;
    }
  }
  EXPECT_GE(solutions, 1);  // degenerate ties may give the same solution twice
  return found;
}

/// Runs the solver from zero forces; returns the forces and the residual.
Eigen::VectorXd gauss_seidel(const Problem& problem, int sweeps, double& residual_m) {
  const auto m = problem.rows.size();
  std::vector<double> forces(m, 0.0), gaps(m, 0.0);
  std::vector<detail::SweepRow> work(m);
  residual_m = solve_gauss_seidel(problem.rows, std::span<const double>(problem.w.data(), m * m), m, sweeps, forces,
                                  gaps, GaussSeidelWorkspace{work, &detail::needle_lane_kernels(KernelIsa::best)});
  return Eigen::Map<Eigen::VectorXd>(forces.data(), static_cast<Eigen::Index>(m));
}

TEST(NeedleGaussSeidel, ConvergesToTheEnumeratedSolutionOfMixedProblems) {
  double worst_n = 0.0;
  for (unsigned seed = 1; seed <= 20; ++seed) {
    const Problem problem = random_problem(3, seed, seed % 2 == 0);  // 9 rows, up to 3^9 active sets
    const Eigen::VectorXd exact = enumerate_solution(problem);
    ASSERT_EQ(exact.size(), 9);
    double residual_m = 0.0;
    const Eigen::VectorXd solved = gauss_seidel(problem, 400, residual_m);
    const double error_n = (solved - exact).lpNorm<Eigen::Infinity>();
    worst_n = std::max(worst_n, error_n);
    EXPECT_LT(error_n, 1e-9) << "seed " << seed;
    EXPECT_LT(residual_m, 1e-12) << "seed " << seed;
  }
  std::printf("largest force error against enumeration after 400 sweeps: %.2e N\n", worst_n);
}

TEST(NeedleGaussSeidel, WarmStartFromTheSolutionStaysThere) {
  const Problem problem = random_problem(2, 7, false);
  const Eigen::VectorXd exact = enumerate_solution(problem);
  const auto m = problem.rows.size();
  std::vector<double> forces(exact.data(), exact.data() + m), gaps(m, 0.0);
  std::vector<detail::SweepRow> work(m);
  const double residual_m =
      solve_gauss_seidel(problem.rows, std::span<const double>(problem.w.data(), m * m), m, 1, forces, gaps,
                         GaussSeidelWorkspace{work, &detail::needle_lane_kernels(KernelIsa::best)});
  for (std::size_t r = 0; r < m; ++r) EXPECT_NEAR(forces[r], exact[static_cast<Eigen::Index>(r)], 1e-12);
  EXPECT_LT(residual_m, 1e-14);
}

TEST(NeedleGaussSeidel, ResidualFallsWithSweepsAndIsZeroOnlyAtTheSolution) {
  const Problem problem = random_problem(3, 11, false);
  const Eigen::VectorXd exact = enumerate_solution(problem);
  double few_m = 0.0, many_m = 0.0;
  const Eigen::VectorXd rough = gauss_seidel(problem, 2, few_m);
  const Eigen::VectorXd fine = gauss_seidel(problem, 60, many_m);
  std::printf("residual after 2 sweeps %.2e m (force error %.2e N), after 60 sweeps %.2e m (%.2e N)\n", few_m,
              (rough - exact).lpNorm<Eigen::Infinity>(), many_m, (fine - exact).lpNorm<Eigen::Infinity>());
  EXPECT_GT(few_m, 1e-9);  // not converged yet, and the residual says so
  EXPECT_LT(many_m, few_m * 1e-3);
  EXPECT_LT((fine - exact).lpNorm<Eigen::Infinity>(), (rough - exact).lpNorm<Eigen::Infinity>() * 1e-3);
}

}  // namespace
}  // namespace nav
