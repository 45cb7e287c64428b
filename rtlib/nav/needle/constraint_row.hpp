#pragma once
// One scalar constraint between the needle and the tissue: a direction applied at a point
// of the needle (interpolated between two nodes) against a tissue point, its gap in the
// free motion and the law that ties the gap to the force. Plain data for the solver.
#include <cstdint>

#include <Eigen/Core>

#include "nav/needle/row_law.hpp"

namespace nav {

/// One row of H and its law. Forces are on the needle along `direction` (newtons); the
/// tissue gets the opposite.
struct ConstraintRow {
  RowLaw law = RowLaw::bilateral;
  std::int32_t slot = 0;  ///< where its force is kept between steps (warm start)
  std::int32_t node = 1;  ///< needle point = (1 - weight) x_node + weight x_node+1
  double weight = 0.0;
  Eigen::Vector3d direction = Eigen::Vector3d::Zero();
  Eigen::Vector3d tissue_point_m = Eigen::Vector3d::Zero();  ///< where the tissue is touched
  std::int32_t tissue_node = -1;  ///< the tissue node that carries that point (-1 stand-alone)
  double gap_free_m = 0.0;
  double cap = 0.0;                   ///< f_p, the cutting force or the friction limit, newtons
  double friction_coefficient = 0.0;  ///< mu of friction_axial and coulomb_pair rows
  std::int32_t linked[2] = {-1, -1};  ///< rows (indices in the active list) a limit depends on
};

/// Whether `next` belongs to the same constraint point as `row`.
inline bool same_constraint_point(const ConstraintRow& row, const ConstraintRow& next) {
  return next.node == row.node && next.weight == row.weight && next.tissue_point_m == row.tissue_point_m;
}

}  // namespace nav
