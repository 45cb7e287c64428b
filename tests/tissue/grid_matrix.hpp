#pragma once
// A sparse symmetric test matrix of the factorisations' tests (SparseCholesky, SparseLdlt).
#include <Eigen/SparseCore>
#include <array>
#include <cstdint>
#include <random>
#include <vector>

namespace nav::testing {

/// The 3D grid Laplacian of side `side` (7-point stencil) plus `shift` on the diagonal, with
/// every off-diagonal entry scaled by a seeded factor in [0.5, 1.5]: symmetric, and positive
/// definite for shift > 0.
inline Eigen::SparseMatrix<double> grid_matrix(int side, double shift, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> scale(0.5, 1.5);
  const int n = side * side * side;
  std::vector<Eigen::Triplet<double>> entries;
  std::vector<double> diagonal(static_cast<std::size_t>(n), shift);
  const auto at = [side](int x, int y, int z) { return (z * side + y) * side + x; };
  for (int z = 0; z < side; ++z)
    for (int y = 0; y < side; ++y)
      for (int x = 0; x < side; ++x)
        for (const auto& [dx, dy, dz] : {std::array{1, 0, 0}, std::array{0, 1, 0}, std::array{0, 0, 1}}) {
          if (x + dx >= side || y + dy >= side || z + dz >= side) continue;
          const int i = at(x, y, z), j = at(x + dx, y + dy, z + dz);
          const double w = scale(rng);
          entries.emplace_back(i, j, -w);
          entries.emplace_back(j, i, -w);
          diagonal[static_cast<std::size_t>(i)] += w;
          diagonal[static_cast<std::size_t>(j)] += w;
        }
  for (int i = 0; i < n; ++i) entries.emplace_back(i, i, diagonal[static_cast<std::size_t>(i)]);
  Eigen::SparseMatrix<double> m(n, n);
  m.setFromTriplets(entries.begin(), entries.end());
  return m;
}

}  // namespace nav::testing
