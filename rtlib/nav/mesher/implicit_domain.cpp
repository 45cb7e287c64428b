#include "nav/mesher/implicit_domain.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace nav {

ImplicitDomain::ImplicitDomain(Field field, const Bounds3& bounds, double feature_size_m)
    : field_(std::move(field)), bounds_(bounds), feature_size_m_(feature_size_m) {}

ImplicitDomain make_ball_domain(const Point3& centre_m, double radius_m) {
  const Point3 reach{radius_m, radius_m, radius_m};
  return ImplicitDomain([centre_m, radius_m](const Point3& p) { return norm(p - centre_m) - radius_m; },
                        Bounds3{centre_m - reach, centre_m + reach}, radius_m);
}

ImplicitDomain make_box_domain(const Bounds3& box_m) {
  const Point3 centre_m = 0.5 * (box_m.min_m + box_m.max_m);
  const Point3 half_m = 0.5 * (box_m.max_m - box_m.min_m);
  const double feature_m = std::min({half_m[0], half_m[1], half_m[2]});
  return ImplicitDomain(
      [centre_m, half_m](const Point3& p) {
        Point3 outside{};
        double inside_m = -1e300;
        for (int a = 0; a < 3; ++a) {
          const double q = std::abs(p[a] - centre_m[a]) - half_m[a];
          outside[a] = std::max(q, 0.0);
          inside_m = std::max(inside_m, q);
        }
        return norm(outside) + std::min(inside_m, 0.0);
      },
      box_m, feature_m);
}

}  // namespace nav
