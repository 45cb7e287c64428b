#pragma once
// Tissue material points for the needle constraints: attached at creation to the nearest
// tissue node (when the tissue moves as a whole) and carried by its displacement.
#include <span>

#include "nav/needle/needle_tissue_model.hpp"

namespace nav {

/// The material point now at `position_m`: its nearest tissue node (the lane kernels' scan, fixed
/// cost per node) and its rest position under the given displacements (may be empty).
TissuePoint tissue_point_at(const NeedleTissueModel& model, const Eigen::Vector3d& position_m,
                            std::span<const double> displacements_m) noexcept;

}  // namespace nav
