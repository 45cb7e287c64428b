#include <algorithm>

#include "nav/tissue/tet_fem_model.hpp"
#include "nav/tissue/tet_fem_tables.hpp"

namespace nav {

namespace {

using detail::TetFemTables;

/// out[3 j + c] = the weighted mean over the patch of j of value(k, c) (value(j, c) alone
/// without patches): what the point a point force on j acts on sees of a nodal field.
template <class NodeValue>
void gather_over_patches(const TetFemTables& tables, std::span<double> out, NodeValue value) noexcept {
  for (std::size_t j = 0; j < static_cast<std::size_t>(tables.node_count); ++j) {
    const auto [first, last] = point_force_patch(tables, j);
    for (std::size_t c = 0; c < 3; ++c) {
      if (first == last) {
        out[3 * j + c] = value(j, c);
        continue;
      }
      double sum = 0.0;
      for (std::size_t k = first; k < last; ++k)
        sum += tables.patch_weights[k] * value(static_cast<std::size_t>(tables.patch_nodes[k]), c);
      out[3 * j + c] = sum;
    }
  }
}

}  // namespace

bool has_rest_step_response(const TetFemModel& model) noexcept {
  const TissueSolverOptions& o = model.options();
  return o.solver == LinearSolver::ldlt_warped && o.integrator != Integrator::explicit_central_difference;
}

bool rest_step_response_m(const TetFemModel& model, std::int32_t node, int axis, std::span<double> out_m,
                          std::span<double> work) noexcept {
  const TetFemTables& tables = model.tables();
  std::fill(out_m.begin(), out_m.end(), 0.0);
  if (!has_rest_step_response(model) || node < 0 || node >= tables.node_count || axis < 0 || axis > 2) return false;
  const std::size_t free3 = 3 * tables.free_nodes.size();
  const std::span<double> local = work.first(free3), scratch = work.subspan(free3, free3);
  std::fill(local.begin(), local.end(), 0.0);
  bool loaded = false;  // the force reaches a free node
  const auto load = [&](std::size_t at, double weight) {
    const std::int32_t free = tables.free_index[at];
    if (free < 0) return;
    local[3 * static_cast<std::size_t>(free) + static_cast<std::size_t>(axis)] += weight;
    loaded = true;
  };
  const auto [first, last] = point_force_patch(tables, static_cast<std::size_t>(node));
  if (first == last) load(static_cast<std::size_t>(node), 1.0);
  for (std::size_t k = first; k < last; ++k)
    load(static_cast<std::size_t>(tables.patch_nodes[k]), tables.patch_weights[k]);
  if (!loaded) return false;
  tables.factor.solve_in_place(local, scratch);
  const double h = tables.options.step_s;
  const double scale = tables.options.integrator == Integrator::implicit_euler ? h * h : 1.0;
  gather_over_patches(tables, out_m, [&](std::size_t n, std::size_t c) {
    const std::int32_t free = tables.free_index[n];
    return free < 0 ? 0.0 : scale * local[3 * static_cast<std::size_t>(free) + c];
  });
  return true;
}

void point_displacements_m(const TetFemModel& model, const TetFemData& data, std::span<double> out_m) noexcept {
  const TetFemTables& tables = model.tables();
  gather_over_patches(tables, out_m, [&](std::size_t n, std::size_t c) {
    return data.positions_m[3 * n + c] - tables.rest_m[3 * n + c];
  });
}

}  // namespace nav
