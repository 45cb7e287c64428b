#include "nav/reduced/reduced_forces.hpp"

#include <algorithm>

#include "nav/reduced/dense_cholesky.hpp"
#include "nav/reduced/stvk_polynomial.hpp"

namespace nav::detail {
namespace {

/// force = -A q - B d (A r x r, B r x 3, row-major).
void stiffness_force(const ReducedTables& t, std::span<const double> a, std::span<const double> b,
                     const ReducedState& state, std::span<double> force) {
  const int r = t.r;
  for (int i = 0; i < r; ++i) {
    double value = dot(a.data() + i * r, state.q.data(), r);
    if (t.has_lift)
      for (int c = 0; c < 3; ++c) value += b[static_cast<std::size_t>(3 * i + c)] * state.prescribed_m[c];
    force[static_cast<std::size_t>(i)] = -value;
  }
}

}  // namespace

void linear_force(const ReducedTables& t, const ReducedState& state, std::span<double> force) noexcept {
  stiffness_force(t, t.stiffness_r, t.stiffness_lift_r, state, force);
}

ForceScratchSizes force_scratch_sizes(const ReducedTables& t) noexcept {
  const auto lanes = static_cast<std::size_t>(t.sample_blocks) * kSampleLanes;
  return {12 * lanes, 9 * lanes,
          static_cast<std::size_t>(t.r) * kSampleLanes + 10 * lanes + corotational_tangent_work_size(t.r)};
}

int evaluate_internal_force(const ReducedTables& t, const ReducedState& state, ForceScratch scratch,
                            std::span<double> force, std::span<double> tangent) noexcept {
  const int r = t.r;
  const bool with_tangent = !tangent.empty();
  if (t.force_kind == ReducedForceKind::stvk_cubic_polynomial) {
    evaluate_stvk_polynomial(t, state.q, scratch.monomials, force, tangent);
    return 0;
  }
  if (t.force_kind == ReducedForceKind::linear) {
    linear_force(t, state, force);
    if (with_tangent) std::copy(t.stiffness_r.begin(), t.stiffness_r.end(), tangent.begin());
    return 0;
  }
  stiffness_force(t, t.cubature_stiffness_r, t.cubature_stiffness_lift_r, state, force);
  if (with_tangent) std::copy(t.cubature_stiffness_r.begin(), t.cubature_stiffness_r.end(), tangent.begin());
  const std::size_t lanes = static_cast<std::size_t>(t.sample_blocks) * kSampleLanes;
  const std::span<double> lane_forces = scratch.tangent_rows.first(static_cast<std::size_t>(r) * kSampleLanes);
  const std::span<double> gradients = scratch.tangent_rows.subspan(lane_forces.size(), 10 * lanes);
  const std::span<double> rows_work = scratch.tangent_rows.subspan(lane_forces.size() + gradients.size());
  std::fill(lane_forces.begin(), lane_forces.end(), 0.0);
  const bool corotational = t.force_kind == ReducedForceKind::corotational_cubature;
  const SampleWork work{scratch.displacements.data(), scratch.rotations.data(), gradients.data(), lane_forces.data()};
  const int inverted =
      corotational ? add_corotational_forces(t, state, false, work) : add_stvk_forces(t, state, false, work);
  for (int b = 0; b < t.sample_blocks && with_tangent; ++b) {
    if (corotational)
      add_corotational_tangent_block(t, b, work, rows_work, tangent);
    else
      add_stvk_tangent_block(t, b, work, tangent);
  }
  // The lanes' sums, combined in a fixed tree.
  static_assert(kSampleLanes == 8, "the lane sum below is written for 8 lanes");
  for (int j = 0; j < r; ++j) {
    const double* s = lane_forces.data() + j * kSampleLanes;
    force[static_cast<std::size_t>(j)] += ((s[0] + s[1]) + (s[2] + s[3])) + ((s[4] + s[5]) + (s[6] + s[7]));
  }
  if (with_tangent && corotational)  // the blocks filled the upper triangle
    for (int i = 1; i < r; ++i)
      for (int j = 0; j < i; ++j)
        tangent[static_cast<std::size_t>(i * r + j)] = tangent[static_cast<std::size_t>(j * r + i)];
  return inverted;
}

}  // namespace nav::detail
