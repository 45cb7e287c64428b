#pragma once
// The constraint rows of one interaction step, built from the needle's free motion and the
// layer and path states, and their compliance W = H A^-1 H^T + W_tissue. Internal to
// rtlib/nav/needle.
#include <span>

#include "nav/needle/needle_tissue_model.hpp"

namespace nav::detail {

/// A point of the needle at rest arclength s and its local frame (tangent, two normals),
/// with the interpolation node and weight of the constraint rows.
struct NeedleFrameAt {
  Eigen::Vector3d point_m, tangent, normal1, normal2;
  int node = 0;
  double weight = 0.0;
};

NeedleFrameAt needle_frame_at(const NeedleModel& model, const NeedleData& data, double arclength_m) noexcept;

/// Layer `layer`'s surface (its TissueSurface, or its plane, at the given displacements) seen
/// from `x_m`: the nearest surface point, its outward normal and x_m's signed distance
/// (negative inside).
SurfaceHit layer_hit(const NeedleTissueModel& model, const NeedleTissueData& data, int layer,
                     const Eigen::Vector3d& x_m, std::span<const double> displacements_m) noexcept;

/// The deepest punctured layer that holds the tip, or -1.
int cutting_layer(const NeedleTissueModel& model, const NeedleTissueData& data, const Eigen::Vector3d& tip_m,
                  std::span<const double> displacements_m) noexcept;

/// The bevel's lateral force on the tip (needle steering): tan(tilt) times the last cutting
/// force, towards the bevel's open side (tip frame +y); zero unless bevel_steering.
Eigen::Vector3d bevel_force_n(const NeedleTissueModel& model, const NeedleTissueData& data) noexcept;

/// Advances the layers' phases for the free tip (first touch, re-entry through a hole) and
/// fills data.rows (data.row_count) with warm-start forces in data.row_forces.
void build_rows(const NeedleTissueModel& model, NeedleTissueData& data,
                std::span<const double> displacements_m) noexcept;

/// Fills data.compliance (row_count rows, compliance_stride apart) and takes the tissue's response to the forces it
/// already carries (applied_forces, in the displacements) out of the rows' free gaps.
void assemble_compliance(const NeedleTissueModel& model, NeedleTissueData& data) noexcept;

/// Displacement of the tissue at `point_m`, carried by tissue node `node`, under the forces
/// not yet carried by the tissue model (the rows' forces minus applied_forces), by the
/// Gaussian kernel or the low-rank compliance (which needs the node; none: no displacement).
Eigen::Vector3d compliant_displacement_m(const NeedleTissueModel& model, const NeedleTissueData& data,
                                         const Eigen::Vector3d& point_m, std::int32_t node) noexcept;

}  // namespace nav::detail
