#pragma once
// The shape of the embedded default liver: a procedural, anatomically plausible adult liver as
// an implicit function, with the landmarks that the embedded liver places on it.
//
// Axes (metres, origin near the centre of the organ's bounding box), patient frame:
//   x: patient's right (-) to left (+); the large right lobe lies at -x;
//   y: posterior (-) to anterior (+);
//   z: inferior (-) to superior (+), towards the head and the diaphragm.
#include "nav/mesh/geometry.hpp"
#include "nav/mesher/implicit_domain.hpp"

namespace nav {

/// Signed field of the liver, about a distance in metres near the surface (negative inside):
/// the smooth union of a large right lobe and a smaller, thinner left lobe. Each lobe is a
/// superellipsoid that is rounder above (the convex diaphragmatic surface) than below (the
/// flatter visceral surface) and tapers towards the left; together about 20 x 15 x 10 cm and
/// 1.5 L.
double liver_field_m(const Point3& point_m);

/// The liver as a meshing domain (liver_field_m, its bounds, its thinnest part).
ImplicitDomain make_liver_domain();

/// Landmarks of the procedural liver, in the frame above.
struct LiverLandmarks {
  Point3 tumour_centre_m{-0.040, -0.005, 0.003};  ///< deep in the right lobe
  double tumour_radius_m = 0.015;
  /// A point inside, straight above the hilum (porta hepatis): the hilum is where the
  /// vertical line through it leaves the visceral (lower) surface, a little posterior.
  Point3 above_hilum_m{0.000, -0.015, 0.0};
  double hilum_radius_m = 0.025;       ///< boundary nodes this close to the hilum attach
  double falciform_x_m = 0.012;        ///< the falciform ligament runs along this plane, between the lobes,
  double falciform_from_y_m = -0.015;  ///< over the upper surface from here forwards (anteriorly)
};

}  // namespace nav
