#pragma once
// A stand-alone insertion rig for the needle-tissue tests: the needle along +x, layers
// facing it, and a driver that moves the base at a constant speed and records the forces.
#include <algorithm>
#include <cmath>
#include <vector>

#include "nav/needle/gauss_seidel.hpp"
#include "nav/needle/needle_step.hpp"
#include "nav/needle/needle_tissue_model.hpp"
#include "nav/needle/needle_tissue_rows.hpp"
#include "needle_test_support.hpp"

namespace nav::testing {

/// A layer whose surface faces the needle (normal -x) at x = surface_x_m.
inline TissueLayer facing_layer(double surface_x_m, double puncture_n, double cutting_n, double friction_n_m) {
  TissueLayer layer;
  layer.surface_point_m = {surface_x_m, 0.0, 0.0};
  layer.outward_normal = {-1.0, 0.0, 0.0};
  layer.puncture_force_n = puncture_n;
  layer.cutting_force_n = cutting_n;
  layer.friction_per_length_n_m = friction_n_m;
  return layer;
}

/// One recorded step.
struct Sample {
  double base_x_m = 0.0, depth_m = 0.0;
  InsertionForces forces;
  double residual_m = 0.0;
  int path_points = 0;
  Eigen::Vector3d tip_m;
};

/// Moves the base along x from its current position to `to_x_m` at `step_m` per step
/// (the last step shorter), recording every step.
inline void drive_to(const NeedleTissueModel& model, NeedleTissueData& data, double to_x_m, double step_m,
                     std::vector<Sample>& record) {
  NeedleTissueInputs inputs;
  double x = data.needle.positions_m[0];
  while (std::abs(to_x_m - x) > 1e-12) {
    x += std::clamp(to_x_m - x, -step_m, step_m);
    inputs.needle.base.position_m = {x, 0.0, 0.0};
    step(model, data, inputs);
    record.push_back({x, data.report.tip_depth_m, data.report.forces, data.report.residual_m,
                      data.report.active_path_points, needle_tip_m(data.needle)});
  }
}

/// The largest violation of the rows' laws after the correction, measured on the corrected
/// needle and the displaced tissue (not on the solver's linear gaps); the tissue point of
/// row r is at tissue_position_m(r).
template <class TissuePosition>
double violation_after_correction(const NeedleTissueData& data, TissuePosition&& tissue_position_m) {
  const std::size_t m = static_cast<std::size_t>(data.row_count);
  std::vector<double> gaps(m);
  std::vector<ConstraintRow> rows(data.rows.begin(), data.rows.begin() + static_cast<std::ptrdiff_t>(m));
  const std::span<const double> forces(data.row_forces.data(), m);
  for (std::size_t r = 0; r < m; ++r) {
    const ConstraintRow& row = rows[r];
    const auto node = [&](int n) {
      return Eigen::Map<const Eigen::Vector3d>(data.needle.positions_m.data() + 3 * static_cast<std::size_t>(n));
    };
    Eigen::Vector3d x = (1.0 - row.weight) * node(row.node);
    if (row.weight > 0.0) x += row.weight * node(row.node + 1);
    gaps[r] = row.direction.dot(x - tissue_position_m(r));
  }
  double worst = 0.0;
  for (std::size_t r = 0; r < m; ++r) {
    const double limit = row_limit_n(rows, r, forces);
    worst = std::max(worst, law_violation_m(rows[r], gaps[r], forces[r], limit));
    if (rows[r].law == RowLaw::coulomb_pair)
      worst = std::max(
          worst, coulomb_disk_violation_m(std::span<const double>(gaps).subspan(r, 2), forces.subspan(r, 2), limit));
  }
  return worst;
}

/// The same with the tissue displaced by the forces not yet carried by the tissue model.
inline double violation_after_correction(const NeedleTissueModel& model, const NeedleTissueData& data) {
  return violation_after_correction(data, [&](std::size_t r) {
    const ConstraintRow& row = data.rows[r];
    return Eigen::Vector3d(row.tissue_point_m +
                           detail::compliant_displacement_m(model, data, row.tissue_point_m, row.tissue_node));
  });
}

}  // namespace nav::testing
