#pragma once
// Surface registration by iterative closest points: tracked or ultrasound points lying on
// the organ are matched to the closest points of its preoperative surface (exact closest
// point on the triangles around the nearest vertex) and the rigid fit repeated until it
// settles. Needs an initial guess within the basin (e.g. a landmark registration).
#include <vector>

#include "nav/calibration/rigid_transform.hpp"
#include "nav/core/error.hpp"
#include "nav/mesh/tet_mesh.hpp"

namespace nav::calibration {

/// Settings of surface_icp.
struct IcpOptions {
  int max_iterations = 100;
  double convergence_m = 1e-9;  // stop when the RMS distance changes less than this
};

/// The result: surface_from_points and the final RMS point-to-surface distance.
struct IcpResult {
  Transform surface_from_points = Transform::Identity();
  double rms_distance_m = 0.0;
  int iterations = 0;
};

/// Registers `points` onto `surface` from `initial` (surface_from_points). Errors: an empty
/// surface, fewer than 6 points, coplanar points (they could slide within their plane).
Result<IcpResult> surface_icp(const TriSurface& surface, const std::vector<Eigen::Vector3d>& points,
                              const Transform& initial, const IcpOptions& options = {});

/// The point of triangle (a, b, c) closest to p.
Eigen::Vector3d closest_point_on_triangle(const Eigen::Vector3d& p, const Eigen::Vector3d& a, const Eigen::Vector3d& b,
                                          const Eigen::Vector3d& c);

}  // namespace nav::calibration
