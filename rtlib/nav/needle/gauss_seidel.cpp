#include "nav/needle/gauss_seidel.hpp"

#include <algorithm>
#include <cmath>

namespace nav {
namespace {

constexpr auto kMaxGroup = static_cast<std::size_t>(kMaxRowsPerPoint);

/// One past the last row of the constraint point whose first row is `first`.
std::size_t group_end(std::span<const ConstraintRow> rows, std::size_t first) {
  std::size_t end = first + 1;
  while (end < rows.size() && end - first < kMaxGroup && same_constraint_point(rows[first], rows[end])) ++end;
  return end;
}

/// Chains the P points' next_point in the sweep order 0, H, 1, H + 1, ... with H = ceil(P / 2):
/// each point of the first half followed by its counterpart of the second. Along a needle
/// path the two are far apart, and alternating between them lets a sweep carry a change
/// from one end of the path to the other: with 32 path points in the liver this order
/// leaves a smaller largest residual after 10 sweeps than row order did after 30.
void interleave_points(std::span<detail::SweepRow> rows) {
  std::size_t points = 0;
  for (std::size_t first = 0; first < rows.size(); first += rows[first].point_rows) ++points;
  const std::size_t half = (points + 1) / 2;
  std::size_t leader = 0, partner = 0;
  for (std::size_t k = 0; k < half; ++k) partner += rows[partner].point_rows;
  detail::SweepRow* previous = nullptr;
  const auto visit = [&](std::size_t first) {
    if (previous != nullptr) previous->next_point = static_cast<std::int32_t>(first);
    previous = &rows[first];
  };
  for (std::size_t k = 0; k < half; ++k) {
    visit(leader);
    leader += rows[leader].point_rows;
    if (k + half < points) {
      visit(partner);
      partner += rows[partner].point_rows;
    }
  }
}

}  // namespace

double coulomb_disk_violation_m(std::span<const double> gaps, std::span<const double> forces, double limit_n) noexcept {
  const double force = std::hypot(forces[0], forces[1]), slip = std::hypot(gaps[0], gaps[1]);
  if (limit_n <= 0.0) return 0.0;                   // no normal force: free to slide
  if (force < limit_n * (1.0 - 1e-6)) return slip;  // stick: no tangential motion
  // Slip: the motion must be opposite to the force, gap = -s f / |f| with s >= 0.
  return std::hypot(gaps[0] + slip * forces[0] / force, gaps[1] + slip * forces[1] / force);
}

double row_limit_n(std::span<const ConstraintRow> rows, std::size_t r, std::span<const double> forces) noexcept {
  return row_force_limit_n(rows[r], forces.data());
}

double law_violation_m(const ConstraintRow& row, double gap_m, double force_n, double limit_n) noexcept {
  const double slack = kForceAtBoundSlack * std::max(1.0, limit_n);
  switch (row.law) {
    case RowLaw::bilateral:
      return std::abs(gap_m);
    case RowLaw::unilateral_capped: {
      const double bounds = std::max({0.0, -force_n, force_n - limit_n}) > slack ? 1.0 : 0.0;
      if (force_n <= slack) return std::max(0.0, -gap_m) + bounds;
      if (force_n >= limit_n - slack) return std::max(0.0, gap_m) + bounds;
      return std::abs(gap_m);
    }
    case RowLaw::friction_axial:
    case RowLaw::coulomb_pair:
    case RowLaw::coulomb_second: {
      // Stick inside the bound (no relative motion); at the bound the slip opposes the force.
      if (std::abs(force_n) > limit_n + slack) return 1.0;
      if (row.law != RowLaw::friction_axial) return 0.0;  // the pair is checked as a disk by the caller
      if (limit_n <= slack) return 0.0;                   // no friction: any slip
      if (force_n >= limit_n - slack) return std::max(0.0, gap_m);
      if (force_n <= -limit_n + slack) return std::max(0.0, -gap_m);
      return std::abs(gap_m);
    }
  }
  return 0.0;
}

const detail::NeedleLaneKernels& detail::needle_lane_kernels(KernelIsa isa) noexcept {
  switch (resolve_kernel_isa(isa)) {
#if NAV_KERNEL_ISA_X86
    case KernelIsa::avx2:
      return needle_lane_kernels_avx2;
    case KernelIsa::avx512:
      return needle_lane_kernels_avx512;
#endif
    default:
      return needle_lane_kernels_baseline;
  }
}

double solve_gauss_seidel(std::span<const ConstraintRow> rows, std::span<const double> w, std::size_t w_stride,
                          int sweeps, std::span<double> forces, std::span<double> gaps,
                          const GaussSeidelWorkspace& work) noexcept {
  const std::size_t m = rows.size();
  for (std::size_t first = 0; first < m;) {
    const std::size_t end = group_end(rows, first);
    for (std::size_t r = first; r < end; ++r) {
      const ConstraintRow& row = rows[r];
      const double diagonal = w[r * w_stride + r];
      work.rows[r] = {row.cap,
                      row.friction_coefficient,
                      diagonal > 0.0 ? 1.0 / diagonal : 0.0,
                      {row.linked[0], row.linked[1]},
                      -1,
                      row.law,
                      static_cast<std::uint8_t>(r == first ? end - first : 0)};
      gaps[r] = row.gap_free_m;
    }
    first = end;
  }
  interleave_points(work.rows.first(m));
  work.kernels->gauss_seidel({m, work.rows.data(), w.data(), w_stride, forces.data(), gaps.data()}, sweeps);
  double worst = 0.0;
  for (std::size_t r = 0; r < m; ++r) {
    const double limit = row_limit_n(rows, r, forces);
    worst = std::max(worst, law_violation_m(rows[r], gaps[r], forces[r], limit));
    if (rows[r].law == RowLaw::coulomb_pair)
      worst = std::max(worst, coulomb_disk_violation_m(gaps.subspan(r, 2), forces.subspan(r, 2), limit));
  }
  return worst;
}

}  // namespace nav
