#pragma once
// A synthetic B-mode ultrasound device: slices the simulated liver (liver_shape.hpp: its
// implicit surface, the tumour of its landmarks, a few vessels as tubes) along the image
// plane, with seeded speckle, a hypoechoic tumour, anechoic vessels, a bright capsule and
// depth attenuation; and says where the tumour truly is in the image (ground truth).
// A device-side simulator (its own thread); OpenCV's blur may allocate.
#include <Eigen/Geometry>
#include <cstdint>
#include <random>
#include <vector>

#include "nav/mesh/geometry.hpp"

namespace nav::ultrasound {

/// The image grid: width_px x height_px square pixels of spacing_m; pixel (u, v) is the
/// point (u * spacing_m, v * spacing_m, 0) of the image frame (x along a row, y in depth).
struct BmodeGeometry {
  std::uint32_t width_px = 256;
  std::uint32_t height_px = 256;
  double spacing_m = 0.3e-3;
};

/// A vessel: a tube of radius_m around the segment from_m .. to_m (liver frame).
struct Vessel {
  Point3 from_m{};
  Point3 to_m{};
  double radius_m = 0.003;
};

/// What the simulated liver holds besides parenchyma (liver frame, metres).
struct BmodeScene {
  Point3 tumour_centre_m{-0.040, -0.005, 0.003};
  double tumour_radius_m = 0.015;
  std::vector<Vessel> vessels;
  double attenuation_np_per_m = 10.0;  ///< round trip, after the scanner's gain compensation
};

/// The default scene: the landmarks' tumour and three vessels that miss it.
BmodeScene default_bmode_scene();

/// Where the tumour is in one frame: its centre projected on the image plane (pixels), its
/// distance from the plane, and the radius of its cross-section (0 when the plane misses it).
struct BmodeTruth {
  double tumour_u_px = 0.0;
  double tumour_v_px = 0.0;
  double tumour_plane_distance_m = 0.0;
  double tumour_section_radius_px = 0.0;
  bool tumour_visible() const noexcept { return tumour_section_radius_px > 0.0; }
};

/// Renders frames; each render draws fresh speckle from the seeded generator, so a given
/// seed and sequence of poses always gives the same frames.
class BmodeSimulator {
 public:
  BmodeSimulator(const BmodeGeometry& geometry, BmodeScene scene, std::uint64_t seed);

  /// Renders the plane whose image frame is `liver_from_image` (liver_from_image, metres) into
  /// `pixels` (width_px * height_px, row-major) and returns the truth.
  BmodeTruth render(const Eigen::Isometry3d& liver_from_image, std::uint8_t* pixels);

  /// The truth alone, for a plane.
  BmodeTruth truth(const Eigen::Isometry3d& liver_from_image) const;

  const BmodeGeometry& geometry() const noexcept { return geometry_; }

 private:
  double echogenicity(const Point3& point_m) const;

  BmodeGeometry geometry_;
  BmodeScene scene_;
  std::mt19937_64 random_;
  std::vector<float> echo_;
};

/// A probe pose that images the tumour: the image plane vertical (depth along -z of the
/// liver), lateral along x, offset `plane_offset_m` along y from the tumour centre, with the
/// tumour `depth_m` below the top edge of the image and centred laterally.
Eigen::Isometry3d plane_through_tumour(const BmodeGeometry& geometry, const BmodeScene& scene, double plane_offset_m,
                                       double depth_m);

}  // namespace nav::ultrasound
