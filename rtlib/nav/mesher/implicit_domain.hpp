#pragma once
// Regions given by an implicit function of position (procedural organs, analytic test shapes).
#include <functional>

#include "nav/mesher/level_set_domain.hpp"

namespace nav {

/// The region where a function of position is negative. The function should behave roughly
/// like a signed distance in metres near its zero level (smooth, gradient about 1).
class ImplicitDomain final : public LevelSetDomain {
 public:
  /// A field: negative inside, positive outside.
  using Field = std::function<double(const Point3&)>;

  /// `bounds` must contain the region; `feature_size_m` (about the thinnest part of the
  /// region) sets the march step (a quarter of it) and the gradient step (1e-4 of it).
  ImplicitDomain(Field field, const Bounds3& bounds, double feature_size_m);

  Bounds3 bounds() const override { return bounds_; }
  double value(const Point3& point_m) const override { return field_(point_m); }

 protected:
  double gradient_step_m() const override { return 1e-4 * feature_size_m_; }
  double march_step_m() const override { return 0.25 * feature_size_m_; }

 private:
  Field field_;
  Bounds3 bounds_;
  double feature_size_m_;
};

/// A ball: the signed distance to the sphere of `radius_m` around `centre_m`.
ImplicitDomain make_ball_domain(const Point3& centre_m, double radius_m);

/// An axis-aligned box: the signed distance to its faces.
ImplicitDomain make_box_domain(const Bounds3& box_m);

}  // namespace nav
