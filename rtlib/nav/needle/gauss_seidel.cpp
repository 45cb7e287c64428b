#include "nav/needle/gauss_seidel.hpp"

#include <algorithm>
#include <cmath>

namespace nav {

namespace {

/// Relative slack under which a force counts as at its bound.
constexpr double kAtBound = 1e-9;

void add_column(std::span<const double> w, std::size_t m, std::size_t column, double change, std::span<double> gaps) {
  if (change == 0.0) return;  // a force held at its bound
  const double* c = w.data() + column * m;
  for (std::size_t i = 0; i < m; ++i) gaps[i] += c[i] * change;
}

constexpr auto kMaxGroup = static_cast<std::size_t>(kMaxRowsPerPoint);

/// One past the last row of the constraint point whose first row is `first`.
std::size_t group_end(std::span<const ConstraintRow> rows, std::size_t first) {
  std::size_t end = first + 1;
  while (end < rows.size() && end - first < kMaxGroup && same_constraint_point(rows[first], rows[end])) ++end;
  return end;
}

/// gaps += W[:, first:end] change, in one pass over the gaps.
void add_columns(std::span<const double> w, std::size_t m, std::size_t first, std::size_t end, const double* change,
                 std::span<double> gaps) {
  const double* a = w.data() + first * m;
  if (end - first == 3) {
    const double* b = a + m;
    const double* c = b + m;
    for (std::size_t i = 0; i < m; ++i) gaps[i] += (a[i] * change[0] + b[i] * change[1]) + c[i] * change[2];
    return;
  }
  for (std::size_t j = first; j < end; ++j) add_column(w, m, j, change[j - first], gaps);
}

double force_of(std::span<const double> forces, std::int32_t row) {
  return row >= 0 ? forces[static_cast<std::size_t>(row)] : 0.0;
}

}  // namespace

double coulomb_disk_violation_m(std::span<const double> gaps, std::span<const double> forces, double limit_n) noexcept {
  const double force = std::hypot(forces[0], forces[1]), slip = std::hypot(gaps[0], gaps[1]);
  if (limit_n <= 0.0) return 0.0;  // no normal force: free to slide
  if (force < limit_n * (1.0 - 1e-6)) return slip;  // stick: no tangential motion
  // Slip: the motion must be opposite to the force, gap = -s f / |f| with s >= 0.
  return std::hypot(gaps[0] + slip * forces[0] / force, gaps[1] + slip * forces[1] / force);
}

double row_limit_n(std::span<const ConstraintRow> rows, std::size_t r, std::span<const double> forces) noexcept {
  const ConstraintRow& row = rows[r];
  switch (row.law) {
    case RowLaw::friction_axial:
      {
      const double a = force_of(forces, row.linked[0]), b = force_of(forces, row.linked[1]);
      return row.cap + row.friction_coefficient * std::sqrt(a * a + b * b);
    }
    case RowLaw::coulomb_pair:
    case RowLaw::coulomb_second:
      return row.friction_coefficient * std::max(0.0, force_of(forces, row.linked[0]));
    case RowLaw::bilateral:
    case RowLaw::unilateral_capped:
      break;
  }
  return row.cap;
}

double law_violation_m(const ConstraintRow& row, double gap_m, double force_n, double limit_n) noexcept {
  const double slack = kAtBound * std::max(1.0, limit_n);
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
      if (limit_n <= slack) return 0.0;  // no friction: any slip
      if (force_n >= limit_n - slack) return std::max(0.0, gap_m);
      if (force_n <= -limit_n + slack) return std::max(0.0, -gap_m);
      return std::abs(gap_m);
    }
  }
  return 0.0;
}

double solve_gauss_seidel(std::span<const ConstraintRow> rows, std::span<const double> w, int sweeps,
                          std::span<double> forces, std::span<double> gaps) noexcept {
  const std::size_t m = rows.size();
  for (std::size_t i = 0; i < m; ++i) gaps[i] = rows[i].gap_free_m;
  for (std::size_t j = 0; j < m; ++j) add_column(w, m, j, forces[j], gaps);
  for (int sweep = 0; sweep < sweeps; ++sweep) {
    for (std::size_t first = 0; first < m;) {
      const std::size_t end = group_end(rows, first), size = end - first;
      // The point's rows in order, their gaps kept up to date within the point's block; the
      // other rows' gaps follow once per point.
      double block[kMaxGroup][kMaxGroup] = {}, inverse_diagonal[kMaxGroup] = {}, change[kMaxGroup] = {};
      for (std::size_t i = 0; i < size; ++i) {
        for (std::size_t j = 0; j < size; ++j) block[i][j] = w[(first + j) * m + first + i];
        inverse_diagonal[i] = block[i][i] > 0.0 ? 1.0 / block[i][i] : 0.0;
      }
      const auto gap_now = [&](std::size_t i) {
        double g = gaps[first + i];
        for (std::size_t j = 0; j < size; ++j) g += block[i][j] * change[j];
        return g;
      };
      for (std::size_t i = 0; i < size; ++i) {
        const std::size_t r = first + i;
        const ConstraintRow& row = rows[r];
        if (row.law == RowLaw::coulomb_second || inverse_diagonal[i] == 0.0) continue;
        if (row.law == RowLaw::coulomb_pair && i + 1 < size) {
          // Both tangent rows, then back onto the disk of radius mu * normal force.
          double f1 = forces[r] - gap_now(i) * inverse_diagonal[i], f2 = forces[r + 1] - gap_now(i + 1) * inverse_diagonal[i + 1];
          const double limit = row_limit_n(rows, r, forces), length = std::sqrt(f1 * f1 + f2 * f2);
          if (length > limit) {
            f1 *= limit / length;
            f2 *= limit / length;
          }
          change[i] += f1 - forces[r];
          change[i + 1] += f2 - forces[r + 1];
          forces[r] = f1;
          forces[r + 1] = f2;
          continue;
        }
        double f = forces[r] - gap_now(i) * inverse_diagonal[i];
        if (row.law == RowLaw::unilateral_capped) f = std::clamp(f, 0.0, row.cap);
        if (row.law == RowLaw::friction_axial) {
          const double limit = row_limit_n(rows, r, forces);
          f = std::clamp(f, -limit, limit);
        }
        change[i] += f - forces[r];
        forces[r] = f;
      }
      add_columns(w, m, first, end, change, gaps);
      first = end;
    }
  }
  double worst = 0.0;
  for (std::size_t r = 0; r < m; ++r) {
    const double limit = row_limit_n(rows, r, forces);
    worst = std::max(worst, law_violation_m(rows[r], gaps[r], forces[r], limit));
    if (rows[r].law == RowLaw::coulomb_pair) worst = std::max(worst, coulomb_disk_violation_m(gaps.subspan(r, 2), forces.subspan(r, 2), limit));
  }
  return worst;
}

}  // namespace nav
