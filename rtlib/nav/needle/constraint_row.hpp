#pragma once
// One scalar constraint between the needle and the tissue: a direction applied at a point
// of the needle (interpolated between two nodes) against a tissue point, its gap in the
// free motion and the law that ties the gap to the force. Plain data for the solver.
#include <cstdint>

#include <Eigen/Core>

namespace nav {

/// The (gap, force) graph of a row, Duriez's characteristic graphs (section 2.5).
enum class RowLaw : std::uint8_t {
  bilateral,         ///< gap = 0, force free (path and tip lateral directions)
  unilateral_capped, ///< gap >= 0, 0 <= force <= cap, gap <= 0 allowed at the cap
                     ///< (puncture up to f_p, cutting up to the cutting force)
  friction_axial,    ///< |force| <= cap + mu |lateral force of the two linked rows|, stick or slip
  coulomb_pair,      ///< first of two tangent rows: |(f1, f2)| <= mu * force of the linked normal row
  coulomb_second,    ///< second of those rows, solved with the first
};

/// One row of H and its law. Forces are on the needle along `direction` (newtons); the
/// tissue gets the opposite.
struct ConstraintRow {
  RowLaw law = RowLaw::bilateral;
  std::int32_t slot = 0;        ///< where its force is kept between steps (warm start)
  std::int32_t node = 1;        ///< needle point = (1 - weight) x_node + weight x_node+1
  double weight = 0.0;
  Eigen::Vector3d direction = Eigen::Vector3d::Zero();
  Eigen::Vector3d tissue_point_m = Eigen::Vector3d::Zero();  ///< where the tissue is touched
  std::int32_t tissue_node = -1;  ///< the tissue node that carries that point (-1 stand-alone)
  double gap_free_m = 0.0;
  double cap = 0.0;             ///< f_p, the cutting force or the friction limit, newtons
  double friction_coefficient = 0.0;  ///< mu of friction_axial and coulomb_pair rows
  std::int32_t linked[2] = {-1, -1};  ///< rows (indices in the active list) a limit depends on
};

/// Rows of one constraint point: at most this many, consecutive, sharing the needle point
/// (node and weight) and the tissue point. The solver and the compliance work per point.
inline constexpr int kMaxRowsPerPoint = 3;

/// Whether `next` belongs to the same constraint point as `row`.
inline bool same_constraint_point(const ConstraintRow& row, const ConstraintRow& next) {
  return next.node == row.node && next.weight == row.weight && next.tissue_point_m == row.tissue_point_m;
}

}  // namespace nav
