#include "nav/mesher/level_set_domain.hpp"

namespace nav {
namespace {

constexpr double kCrossingTolerance_m = 1e-10;

}  // namespace

Point3 LevelSetDomain::gradient(const Point3& point_m) const {
  return central_difference(point_m, gradient_step_m(), [this](const Point3& p) { return value(p); });
}

std::optional<Point3> LevelSetDomain::crossing_along(const Point3& point_m, const Point3& direction,
                                                     double max_distance_m) const {
  const double start_value = value(point_m);
  if (start_value == 0.0) return point_m;
  const bool start_inside = start_value < 0.0;
  // March until the sign changes: the crossing lies in (near_m, far_m].
  const double step_m = march_step_m();
  double near_m = 0.0;
  double far_m = 0.0;
  bool bracketed = false;
  while (!bracketed && near_m < max_distance_m) {
    far_m = near_m + step_m;
    bracketed = (value(point_m + far_m * direction) < 0.0) != start_inside;
    if (!bracketed) near_m = far_m;
  }
  if (!bracketed) return std::nullopt;
  while (far_m - near_m > kCrossingTolerance_m) {
    const double mid_m = 0.5 * (near_m + far_m);
    if ((value(point_m + mid_m * direction) < 0.0) == start_inside) {
      near_m = mid_m;
    } else {
      far_m = mid_m;
    }
  }
  return point_m + (0.5 * (near_m + far_m)) * direction;
}

Point3 LevelSetDomain::project_to_boundary(const Point3& point_m) const {
  const double f = value(point_m);
  if (f == 0.0) return point_m;
  const Point3 g = gradient(point_m);
  const double g_norm = norm(g);
  if (g_norm == 0.0) return point_m;
  // Downhill when outside, uphill when inside: towards the zero level either way.
  const Point3 direction = ((f > 0.0 ? -1.0 : 1.0) / g_norm) * g;
  const Bounds3 box = bounds();
  const double reach_m = norm(box.max_m - box.min_m);
  return crossing_along(point_m, direction, reach_m).value_or(point_m);
}

}  // namespace nav
