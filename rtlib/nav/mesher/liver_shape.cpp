#include "nav/mesher/liver_shape.hpp"

#include <algorithm>
#include <cmath>

namespace nav {
namespace {

/// A lobe: a superellipsoid around `centre_m` with semi-axes along x and y, a taller upper
/// half (exponent 2, a rounded dome) and a flatter lower half (exponent 3); its heights shrink
/// by `taper` per semi-axis towards +x (the patient's left).
struct Lobe {
  Point3 centre_m;
  double half_x_m;
  double half_y_m;
  double up_m;
  double down_m;
  double taper;

  /// About the distance to the lobe's surface near it (scaled by its smallest half-axis).
  double field_m(const Point3& p) const {
    const double u = (p[0] - centre_m[0]) / half_x_m;
    const double v = (p[1] - centre_m[1]) / half_y_m;
    const double height = 1.0 - taper * std::clamp(u, -1.0, 1.0);
    const double dz = p[2] - centre_m[2];
    const double w = std::abs(dz) / (height * (dz >= 0.0 ? up_m : down_m));
    const double radius = std::sqrt(u * u + v * v + (dz >= 0.0 ? w * w : w * w * w));
    return (radius - 1.0) * down_m;
  }
};

// Right lobe: large, tall at the patient's right; left lobe: thinner, higher and more anterior.
const Lobe kRightLobe{{-0.035, 0.000, -0.005}, 0.070, 0.075, 0.060, 0.035, 0.20};
const Lobe kLeftLobe{{0.050, 0.015, 0.010}, 0.065, 0.050, 0.026, 0.016, 0.35};
constexpr double kBlend_m = 0.025;  // width of the smooth union between the lobes

/// Polynomial smooth minimum: min(a, b) rounded over a width k.
double smooth_min(double a, double b, double k) {
  const double h = std::max(k - std::abs(a - b), 0.0) / k;
  return std::min(a, b) - 0.25 * h * h * k;
}

}  // namespace

double liver_field_m(const Point3& point_m) {
  return smooth_min(kRightLobe.field_m(point_m), kLeftLobe.field_m(point_m), kBlend_m);
}

ImplicitDomain make_liver_domain() {
  // The extent of the shape (-0.105 .. 0.114, -0.075 .. 0.079, -0.040 .. 0.057) plus 1 cm.
  const Bounds3 bounds{{-0.115, -0.085, -0.050}, {0.125, 0.090, 0.070}};
  constexpr double kThinnest_m = 0.02;
  return ImplicitDomain(liver_field_m, bounds, kThinnest_m);
}

}  // namespace nav
