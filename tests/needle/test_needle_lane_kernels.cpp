// The needle solver's lane kernels (needle_lane_kernels.hpp) in every instruction set this
// build and CPU run give bitwise the baseline's results: on projected Gauss-Seidel problems
// with every row law (friction and Coulomb rows, points of one to three rows; W's columns
// packed or padded), and on the needle inserted into the reduced embedded liver until 32 path
// points hold it (the scene of `navbench needle`), hashed after the insertion and a wobbling
// hold; their row combinations
// (the compliance assembly's products) give the bits of the definition, term by term in order,
// their nearest-node scans the node of the plain scan in node order, ties and NaNs too, and
// their transpositions and mirrors the values of the plain loops.
// An instruction set the build or CPU lacks is refused by name.
#include <gtest/gtest.h>

#include <algorithm>
#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <limits>
#include <random>
#include <vector>

#include "../../apps/navbench/bench_needle.hpp"
#include "nav/needle/gauss_seidel.hpp"
#include "needle_test_support.hpp"
#include "support/kernel_isas.hpp"

namespace nav {
namespace {

/// A mixed problem of `points` constraint points: path points (two bilateral rows and a
/// friction row linked to them), contact points (a capped normal row and a Coulomb pair)
/// and single capped rows, W = B B^T / m + c I from a seeded RNG, warm-started.
struct MixedProblem {
  std::vector<ConstraintRow> rows;
  std::vector<double> w, warm_start;
};

MixedProblem mixed_problem(int points, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  MixedProblem problem;
  for (int p = 0; p < points; ++p) {
    const int kind = p % 3, first = static_cast<int>(problem.rows.size());
    const auto add = [&](RowLaw law, double cap, double mu) {
      ConstraintRow row;
      row.law = law;
      row.node = 1 + p;  // the rows of one point share node, weight and tissue point
      row.tissue_point_m = Eigen::Vector3d(0.01 * p, 0.0, 0.0);
      row.cap = cap;
      row.friction_coefficient = mu;
      row.gap_free_m = 2e-3 * unit(rng);
      problem.rows.push_back(row);
    };
    if (kind == 0) {
      add(RowLaw::bilateral, 0.0, 0.0);
      add(RowLaw::bilateral, 0.0, 0.0);
      add(RowLaw::friction_axial, 0.05, 0.1);
      problem.rows.back().linked[0] = first;
      problem.rows.back().linked[1] = first + 1;
    } else if (kind == 1) {
      add(RowLaw::unilateral_capped, 0.5, 0.0);
      add(RowLaw::coulomb_pair, 0.0, 0.3);
      add(RowLaw::coulomb_second, 0.0, 0.3);
      problem.rows[static_cast<std::size_t>(first + 1)].linked[0] = first;
      problem.rows[static_cast<std::size_t>(first + 2)].linked[0] = first;
    } else {
      add(RowLaw::unilateral_capped, 0.3, 0.0);
    }
  }
  const auto m = static_cast<Eigen::Index>(problem.rows.size());
  Eigen::MatrixXd b(m, m);
  for (Eigen::Index i = 0; i < m; ++i)
    for (Eigen::Index j = 0; j < m; ++j) b(i, j) = unit(rng);
  const Eigen::MatrixXd w = 1e-3 * (b * b.transpose() / static_cast<double>(m) + 0.2 * Eigen::MatrixXd::Identity(m, m));
  problem.w.assign(w.data(), w.data() + w.size());
  for (Eigen::Index i = 0; i < m; ++i) problem.warm_start.push_back(i % 4 == 0 ? 0.0 : 0.1 * unit(rng));
  return problem;
}

/// Hash of the forces and gaps after `sweeps` sweeps in `isa`'s kernels, and the residual;
/// W's columns `padding` values apart beyond m, the padding NaN (which must never be read).
std::uint64_t solved_hash(const MixedProblem& problem, int sweeps, KernelIsa isa, double& residual_m,
                          std::size_t padding = 0) {
  const std::size_t m = problem.rows.size(), stride = m + padding;
  std::vector<double> w(m * stride, std::nan(""));
  for (std::size_t j = 0; j < m; ++j)
    std::copy_n(problem.w.begin() + static_cast<std::ptrdiff_t>(j * m), m,
                w.begin() + static_cast<std::ptrdiff_t>(j * stride));
  std::vector<double> forces = problem.warm_start, gaps(m, 0.0);
  std::vector<detail::SweepRow> work(m);
  residual_m = solve_gauss_seidel(problem.rows, w, stride, sweeps, forces, gaps,
                                  GaussSeidelWorkspace{work, &detail::needle_lane_kernels(isa)});
  return testing::bits_hash({forces, gaps});
}

TEST(NeedleLaneKernels, EveryVariantSolvesMixedProblemsToTheBaselineBits) {
  int compared = 0;
  for (int points : {1, 2, 5, 11, 33}) {  // up to 97 rows, as 32 path points and a tip row
    for (unsigned seed = 1; seed <= 3; ++seed) {
      const MixedProblem problem = mixed_problem(points, seed);
      double baseline_m = 0.0;
      const std::uint64_t baseline = solved_hash(problem, 30, KernelIsa::baseline, baseline_m);
      EXPECT_TRUE(std::isfinite(baseline_m));
      for (KernelIsa isa : testing::available_kernel_isas()) {
        double residual_m = 0.0;
        for (std::size_t padding : {0, 3, 8}) {
          EXPECT_EQ(solved_hash(problem, 30, isa, residual_m, padding), baseline)
              << kernel_isa_name(isa) << ", " << points << " points, columns padded by " << padding;
          EXPECT_EQ(residual_m, baseline_m) << kernel_isa_name(isa);
          ++compared;
        }
      }
    }
  }
  std::printf("%d solves compared bitwise with the baseline kernels (%zu instruction sets)\n", compared,
              testing::available_kernel_isas().size());
}

/// out_r = sum_k c_rk dense_(source_rk), k in order, value by value: the specification of
/// combine_rows written apart from the kernels.
std::vector<double> combined_by_definition(const detail::RowCombination& p) {
  std::vector<double> out(p.rows * p.out_stride, 0.0);
  for (std::size_t r = 0; r < p.rows; ++r) {
    const std::size_t width =
        p.lower_triangle
            ? std::min(p.width, (r + detail::kCombinedLanes) / detail::kCombinedLanes * detail::kCombinedLanes)
            : p.width;
    for (std::size_t i = 0; i < width; ++i) {
      double v = 0.0;
      for (std::size_t k = 0; k < p.terms; ++k) {
        const double term = p.coefficients[r * p.term_stride + k] *
                            p.dense[static_cast<std::size_t>(p.sources[r * p.term_stride + k]) * p.dense_stride + i];
        v = k == 0 ? term : v + term;
      }
      out[r * p.out_stride + i] = v;
    }
  }
  return out;
}

TEST(NeedleLaneKernels, EveryVariantCombinesRowsToTheDefinitionsBits) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const std::size_t rows = 37, dense_rows = 29, width = 40, stride = 9;
  std::vector<double> coefficients(rows * stride), dense(dense_rows * width);
  std::vector<std::int32_t> sources(rows * stride);
  for (double& c : coefficients) c = unit(rng);
  for (double& d : dense) d = unit(rng) * std::exp(8.0 * unit(rng));  // magnitudes apart: order matters
  for (std::int32_t& s : sources) s = static_cast<std::int32_t>(rng() % dense_rows);
  int compared = 0;
  for (std::size_t terms : {1, 3, 4, 6, 9})
    for (bool lower : {false, true}) {
      detail::RowCombination product{
          rows, terms, stride, coefficients.data(), sources.data(), dense.data(), width, width, lower, nullptr, width};
      const std::vector<double> expected = combined_by_definition(product);
      for (KernelIsa isa : testing::available_kernel_isas()) {
        std::vector<double> out(rows * width, 0.0);
        product.out = out.data();
        detail::needle_lane_kernels(isa).combine_rows(product);
        EXPECT_EQ(out, expected) << kernel_isa_name(isa) << ", " << terms << " terms"
                                 << (lower ? ", lower triangle" : "");
        ++compared;
      }
    }
  std::printf("%d row combinations compared bitwise with their definition\n", compared);
}

TEST(NeedleLaneKernels, EveryVariantTransposesAndMirrorsValueForValue) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  int compared = 0;
  // Sizes below, at and across whole 8 x 8 blocks; strides wider than the block.
  for (std::size_t rows : {0, 1, 7, 8, 9, 16, 23, 97})
    for (std::size_t cols : {0, 3, 8, 15, 90}) {
      const std::size_t src_stride = cols + 5, dst_stride = rows + 3;
      std::vector<double> src(rows * src_stride);
      for (double& v : src) v = unit(rng);
      std::vector<double> expected(cols * dst_stride, -7.0);  // untouched outside the block
      for (std::size_t r = 0; r < rows; ++r)
        for (std::size_t c = 0; c < cols; ++c) expected[c * dst_stride + r] = src[r * src_stride + c];
      for (KernelIsa isa : testing::available_kernel_isas()) {
        std::vector<double> dst(cols * dst_stride, -7.0);
        detail::needle_lane_kernels(isa).transpose({src.data(), src_stride, rows, cols, dst.data(), dst_stride});
        EXPECT_EQ(dst, expected) << kernel_isa_name(isa) << ", " << rows << " x " << cols;
        ++compared;
      }
    }
  for (std::size_t n : {0, 1, 5, 8, 9, 16, 17, 24, 97})
    for (std::size_t stride : {n, n + 4}) {
      std::vector<double> lower(n * stride);
      for (double& v : lower) v = unit(rng);
      std::vector<double> expected = lower;
      for (std::size_t s = 0; s < n; ++s)
        for (std::size_t r = s + 1; r < n; ++r) expected[s * stride + r] = lower[r * stride + s];
      for (KernelIsa isa : testing::available_kernel_isas()) {
        std::vector<double> a = lower;
        detail::needle_lane_kernels(isa).mirror_lower(a.data(), n, stride);
        EXPECT_EQ(a, expected) << kernel_isa_name(isa) << ", n " << n << ", stride " << stride;
        ++compared;
      }
    }
  std::printf("%d transpositions and mirrors compared value for value with the plain loops\n", compared);
}

/// Squared distance of node n from the query's point, summed x, y, then z.
double squared_distance(const detail::NearestNodeQuery& q, std::size_t n) {
  double d[3];
  for (std::size_t c = 0; c < 3; ++c)
    d[c] = q.rest_m[3 * n + c] + (n < q.displaced ? q.displacements_m[3 * n + c] : 0.0) - q.point_m[c];
  return (d[0] * d[0] + d[1] * d[1]) + d[2] * d[2];
}

/// The nearest node by the plain scan in node order that nearest_node must match: node 0
/// whatever its distance, then each node strictly nearer than the best so far.
std::int32_t nearest_by_scan(const detail::NearestNodeQuery& q) {
  std::int32_t nearest = -1;
  double best = 0.0;
  for (std::size_t n = 0; n < q.nodes; ++n) {
    const double d2 = squared_distance(q, n);
    if (nearest < 0 || d2 < best) {
      best = d2;
      nearest = static_cast<std::int32_t>(n);
    }
  }
  return nearest;
}

TEST(NeedleLaneKernels, EveryVariantFindsTheNearestNodeOfThePlainScan) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  // Coordinates on a coarse grid, so that several nodes are often nearest (ties).
  const auto grid = [&](double step, double half_steps) { return step * std::round(half_steps * unit(rng)); };
  int compared = 0, tied = 0;
  for (std::size_t nodes : {0, 1, 2, 7, 8, 9, 17, 100, 4293}) {
    std::vector<double> rest(3 * nodes), displacements(3 * nodes);
    for (double& x : rest) x = grid(0.01, 3.0);
    for (double& u : displacements) u = grid(0.01, 1.0);
    for (int trial = 0; trial < 12; ++trial) {
      std::vector<double> r = rest;
      if (trial == 3 && nodes > 0) r[0] = std::nan("");                // node 0 at NaN: it stays the answer
      if (trial == 4 && nodes > 5) r[3 * (nodes / 2)] = std::nan("");  // a NaN elsewhere never wins
      if (trial == 5 && nodes > 1) r[3 * (nodes - 1)] = std::numeric_limits<double>::infinity();
      detail::NearestNodeQuery q;
      q.rest_m = r.data();
      q.displacements_m = displacements.data();
      q.nodes = nodes;
      q.displaced = trial % 3 == 0 ? nodes : (trial % 3 == 1 ? nodes / 3 : 0);  // all, some, none displaced
      for (double& c : q.point_m) c = grid(0.01, 3.0);
      const std::int32_t expected = nearest_by_scan(q);
      int nearest = 0;
      for (std::size_t n = 0; n < nodes; ++n)
        nearest += squared_distance(q, n) == squared_distance(q, static_cast<std::size_t>(expected));
      tied += nearest > 1 ? 1 : 0;
      for (KernelIsa isa : testing::available_kernel_isas()) {
        EXPECT_EQ(detail::needle_lane_kernels(isa).nearest_node(q), expected)
            << kernel_isa_name(isa) << ", " << nodes << " nodes, trial " << trial;
        ++compared;
      }
    }
  }
  EXPECT_GT(tied, 10);  // the first of equals was put to the test
  std::printf("%d nearest-node scans compared with the plain scan, %d of the queries with tied nearest nodes\n",
              compared, tied);
}

/// The reduced liver and its approach, built once for the cases of this program.
struct LiverFixture {
  navbench::needle_scenes::EmbeddedLiverScene liver;
  ReducedModel tissue = navbench::needle_scenes::reduced_liver(liver);
  navbench::needle_scenes::Approach approach = navbench::needle_scenes::approach_tumour(liver);
};

const LiverFixture& liver_fixture() {
  static const LiverFixture fixture;
  return fixture;
}

/// Inserts the 20-element needle into the reduced liver with `isa`'s kernels until 32 path
/// points hold it, holds it for 200 wobbling ticks; returns the hash of every tick's needle
/// positions, slot forces and tissue coordinates.
std::uint64_t liver_run(KernelIsa isa, int& path_points, int& rows) {
  using namespace navbench::needle_scenes;
  const LiverFixture& f = liver_fixture();
  NeedleTissueScene scene = liver_capsule(f.approach, kReducedPathSpacingM);
  scene.kernel_isa = isa;
  const ReducedCoupledNeedleModel model =
      make_coupled_needle_model(needle(20), scene, f.tissue, f.liver.liver.mesh, 64, 1).value();
  ReducedCoupledNeedleData data = make_coupled_needle_data(model, f.approach.base_at(0.0)).value();
  std::uint64_t hash = 0;
  double advanced_m = 0.0;
  const auto tick = [&](const NeedlePose& base) {
    step(model, data, NeedleInputs{base, {}, {}});
    hash = 31 * hash +
           testing::bits_hash({data.interaction.needle.positions_m, data.interaction.slot_forces, data.tissue.q});
  };
  while (data.interaction.report.active_path_points < 32 && advanced_m < 0.1)
    tick(f.approach.base_at(advanced_m += 2e-5));
  for (int k = 0; k < 200; ++k) tick(f.approach.wobbled_base(advanced_m, k));
  path_points = data.interaction.report.active_path_points;
  rows = data.interaction.row_count;
  return hash;
}

TEST(NeedleLaneKernels, EveryVariantInsertsIntoTheReducedLiverWithTheBaselineBits) {
  if (testing::available_kernel_isas().size() < 2) GTEST_SKIP() << "only the baseline kernels here: nothing to compare";
  int points = 0, rows = 0;
  const std::uint64_t baseline = liver_run(KernelIsa::baseline, points, rows);
  ASSERT_EQ(points, 32);
  EXPECT_GE(rows, 96);
  std::printf("reduced liver, 32 path points, %d rows: baseline hash 0x%016" PRIx64 "\n", rows, baseline);
  for (KernelIsa isa : testing::available_kernel_isas()) {
    if (isa == KernelIsa::baseline) continue;
    EXPECT_EQ(liver_run(isa, points, rows), baseline) << kernel_isa_name(isa);
  }
}

TEST(NeedleLaneKernels, AnUnavailableInstructionSetIsRefusedByName) {
  NeedleTissueScene scene;
  std::vector<KernelIsa> refused = {static_cast<KernelIsa>(99)};  // no such instruction set
  for (KernelIsa isa : {KernelIsa::avx2, KernelIsa::avx512})
    if (!kernel_isa_available(isa)) refused.push_back(isa);
  for (KernelIsa isa : refused) {
    scene.kernel_isa = isa;
    const auto model = make_needle_tissue_model(NeedleParameters{}, scene);
    ASSERT_FALSE(model.ok());
    EXPECT_EQ(model.error().field, "scene.kernel_isa");
  }
  scene.kernel_isa = KernelIsa::best;
  const auto best = make_needle_tissue_model(NeedleParameters{}, scene);
  ASSERT_TRUE(best.ok());
  EXPECT_EQ(best.value().lane_kernels, &detail::needle_lane_kernels(KernelIsa::best));
}

}  // namespace
}  // namespace nav
