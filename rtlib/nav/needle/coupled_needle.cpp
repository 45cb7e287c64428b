// The parts of the coupled needle that do not depend on the tissue model: the coupling's
// checks, the gathering of the constraint forces into the tissue's point forces, and the
// placing of a free needle.
#include <algorithm>
#include <cmath>

#include "nav/needle/coupled_needle_step.hpp"

namespace nav::detail {

namespace {

/// Adds `force` on `node` to the list, merging with an entry for the same node.
void add_point_force(std::span<PointForce> forces, std::size_t& count, std::int32_t node,
                     const Eigen::Vector3d& force) {
  for (std::size_t k = 0; k < count; ++k)
    if (forces[k].node == node) {
      for (int c = 0; c < 3; ++c) forces[k].force_n[static_cast<std::size_t>(c)] += force[c];
      return;
    }
  forces[count++] = PointForce{node, {force[0], force[1], force[2]}};
}

}  // namespace

Status validate_coupling(const NeedleTissueScene& scene, std::size_t max_point_forces,
                         int needle_steps_per_tissue_step) {
  if (scene.layers.empty()) return Error{.message = "the coupled scene needs a layer", .field = "scene.layers"};
  if (needle_steps_per_tissue_step < 1)
    return Error{.message = "must be at least 1", .field = "needle_steps_per_tissue_step"};
  if (max_point_forces < 1) return Error{.message = "must be at least 1", .field = "max_point_forces"};
  return Done{};
}

std::size_t gather_point_forces(const NeedleTissueData& interaction, std::span<PointForce> out, std::size_t max_forces,
                                int& dropped) noexcept {
  std::size_t count = 0;
  for (int r = 0; r < interaction.row_count; ++r) {
    const ConstraintRow& row = interaction.rows[static_cast<std::size_t>(r)];
    if (row.tissue_node < 0) continue;
    add_point_force(out, count, row.tissue_node, -interaction.row_forces[static_cast<std::size_t>(r)] * row.direction);
  }
  dropped = 0;
  if (count <= max_forces) return count;
  // Keep the largest: a stable order by magnitude, then by node.
  std::sort(out.begin(), out.begin() + static_cast<std::ptrdiff_t>(count),
            [](const PointForce& a, const PointForce& b) {
              const double na = std::hypot(a.force_n[0], a.force_n[1], a.force_n[2]);
              const double nb = std::hypot(b.force_n[0], b.force_n[1], b.force_n[2]);
              return na != nb ? na > nb : a.node < b.node;
            });
  dropped = static_cast<int>(count - max_forces);
  return max_forces;
}

}  // namespace nav::detail

namespace nav {

bool place_free_needle(const NeedleTissueModel& model, NeedleTissueData& data, const NeedlePose& base) noexcept {
  for (const LayerState& layer : data.layers)
    if (layer.phase != LayerPhase::outside) return false;
  for (const PathPoint& point : data.path)
    if (point.active) return false;
  if (!is_finite_unit_pose(base)) return false;
  place_straight_needle(model.needle, data.needle, base);
  return true;
}

}  // namespace nav
