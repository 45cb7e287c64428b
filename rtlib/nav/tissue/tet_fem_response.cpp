#include <algorithm>

#include "nav/tissue/tet_fem_model.hpp"
#include "nav/tissue/tet_fem_tables.hpp"

namespace nav {

bool has_rest_step_response(const TetFemModel& model) noexcept {
  const TissueSolverOptions& o = model.options();
  return o.solver == LinearSolver::ldlt_warped && o.integrator != Integrator::explicit_central_difference;
}

bool rest_step_response_m(const TetFemModel& model, std::int32_t node, int axis, std::span<double> out_m,
                          std::span<double> work) noexcept {
  const detail::TetFemTables& tables = model.tables();
  std::fill(out_m.begin(), out_m.end(), 0.0);
  if (!has_rest_step_response(model) || node < 0 || node >= tables.node_count || axis < 0 || axis > 2) return false;
  const std::int32_t free = tables.free_index[static_cast<std::size_t>(node)];
  if (free < 0) return false;
  const std::size_t free3 = 3 * tables.free_nodes.size();
  const std::span<double> local = work.first(free3), scratch = work.subspan(free3, free3);
  std::fill(local.begin(), local.end(), 0.0);
  local[3 * static_cast<std::size_t>(free) + static_cast<std::size_t>(axis)] = 1.0;
  tables.factor.solve_in_place(local, scratch);
  const double h = tables.options.step_s;
  const double scale = tables.options.integrator == Integrator::implicit_euler ? h * h : 1.0;
  for (std::size_t k = 0; k < tables.free_nodes.size(); ++k)
    for (std::size_t c = 0; c < 3; ++c)
      out_m[3 * static_cast<std::size_t>(tables.free_nodes[k]) + c] = scale * local[3 * k + c];
  return true;
}

}  // namespace nav
