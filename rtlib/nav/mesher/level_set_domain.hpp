#pragma once
// Regions given by a scalar field (negative inside, positive outside, boundary at zero):
// the common part of label volumes and implicit functions.
#include <optional>

#include "nav/mesher/meshing_domain.hpp"

namespace nav {

/// A region whose boundary is the zero level of a scalar field. Inside means a negative value;
/// projection follows the field's gradient towards the zero level, brackets the crossing by
/// marching and refines it by bisection.
class LevelSetDomain : public MeshingDomain {
 public:
  /// The field at a point: negative inside, positive outside.
  virtual double value(const Point3& point_m) const = 0;

  bool contains(const Point3& point_m) const override { return value(point_m) < 0.0; }
  Point3 project_to_boundary(const Point3& point_m) const override;

  /// The direction of steepest ascent of the field (not necessarily normalised): by default
  /// the central-difference gradient of value() with the domain's step. Domains whose field
  /// is flat away from the boundary give a better direction.
  virtual Point3 gradient(const Point3& point_m) const;

  /// The zero crossing met first on the ray from `point_m` along the unit `direction`, within
  /// `max_distance_m`, to 1e-10 m or better; nullopt if the field keeps its sign that far.
  std::optional<Point3> crossing_along(const Point3& point_m, const Point3& direction, double max_distance_m) const;

 protected:
  LevelSetDomain() = default;
  /// Finite-difference step of gradient(), metres.
  virtual double gradient_step_m() const = 0;
  /// March step used to bracket a crossing (smaller than the thinnest feature), metres.
  virtual double march_step_m() const = 0;

  /// Central differences of `field` (a function of a point) at `point_m` with step `step_m`.
  template <typename Field>
  static Point3 central_difference(const Point3& point_m, double step_m, const Field& field) {
    Point3 g{};
    for (int a = 0; a < 3; ++a) {
      Point3 plus = point_m;
      Point3 minus = point_m;
      plus[a] += step_m;
      minus[a] -= step_m;
      g[a] = (field(plus) - field(minus)) / (2.0 * step_m);
    }
    return g;
  }
};

}  // namespace nav
