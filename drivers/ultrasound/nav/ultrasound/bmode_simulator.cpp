#include "nav/ultrasound/bmode_simulator.hpp"

#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>

#include "nav/mesher/liver_shape.hpp"

namespace nav::ultrasound {
namespace {

constexpr double kParenchyma = 0.55;
constexpr double kOutside = 0.35;
constexpr double kTumour = 0.14;
constexpr double kVessel = 0.03;
constexpr double kCapsule = 0.9;
constexpr double kCapsuleWidth_m = 0.6e-3;
constexpr double kEdgeWidth_m = 0.4e-3;
constexpr double kSpeckleSigmaPx = 0.8;

double distance_to_segment(const Point3& point, const Point3& from, const Point3& to) {
  const Point3 axis = to - from;
  const double t = std::clamp(dot(point - from, axis) / dot(axis, axis), 0.0, 1.0);
  return norm(point - (from + t * axis));
}

/// 0 well inside a region whose signed distance is `distance_m`, 1 well outside.
double outside_weight(double distance_m) { return 0.5 * (1.0 + std::tanh(distance_m / kEdgeWidth_m)); }

}  // namespace

BmodeScene default_bmode_scene() {
  BmodeScene scene;
  const LiverLandmarks landmarks;
  scene.tumour_centre_m = landmarks.tumour_centre_m;
  scene.tumour_radius_m = landmarks.tumour_radius_m;
  scene.vessels = {{{0.0, -0.015, -0.025}, {-0.09, -0.01, -0.025}, 0.005},
                   {{-0.02, -0.03, 0.035}, {-0.07, 0.03, 0.035}, 0.003},
                   {{0.03, -0.02, 0.0}, {0.07, 0.03, 0.01}, 0.003}};
  return scene;
}

BmodeSimulator::BmodeSimulator(const BmodeGeometry& geometry, BmodeScene scene, std::uint64_t seed)
    : geometry_(geometry),
      scene_(std::move(scene)),
      random_(seed),
      echo_(std::size_t{geometry.width_px} * geometry.height_px) {}

double BmodeSimulator::echogenicity(const Point3& point_m) const {
  const double liver_m = liver_field_m(point_m);
  double echo = kOutside + (kParenchyma - kOutside) * (1.0 - outside_weight(liver_m));
  const double tumour_m = norm(point_m - scene_.tumour_centre_m) - scene_.tumour_radius_m;
  echo += (kTumour - echo) * (1.0 - outside_weight(tumour_m));
  for (const Vessel& vessel : scene_.vessels) {
    const double vessel_m = distance_to_segment(point_m, vessel.from_m, vessel.to_m) - vessel.radius_m;
    echo += (kVessel - echo) * (1.0 - outside_weight(vessel_m));
  }
  const double capsule = liver_m / kCapsuleWidth_m;
  return echo + (kCapsule - echo) * std::exp(-capsule * capsule);
}

BmodeTruth BmodeSimulator::truth(const Eigen::Isometry3d& liver_from_image) const {
  const Eigen::Vector3d centre(scene_.tumour_centre_m[0], scene_.tumour_centre_m[1], scene_.tumour_centre_m[2]);
  const Eigen::Vector3d in_image = liver_from_image.inverse() * centre;
  BmodeTruth truth;
  truth.tumour_u_px = in_image.x() / geometry_.spacing_m;
  truth.tumour_v_px = in_image.y() / geometry_.spacing_m;
  truth.tumour_plane_distance_m = in_image.z();
  const double section_m2 = scene_.tumour_radius_m * scene_.tumour_radius_m - in_image.z() * in_image.z();
  truth.tumour_section_radius_px = section_m2 > 0.0 ? std::sqrt(section_m2) / geometry_.spacing_m : 0.0;
  return truth;
}

BmodeTruth BmodeSimulator::render(const Eigen::Isometry3d& liver_from_image, std::uint8_t* pixels) {
  const int width = static_cast<int>(geometry_.width_px);
  const int height = static_cast<int>(geometry_.height_px);
  // Fully developed speckle: Rayleigh-distributed amplitude (mean 1), then a little blur for
  // the grain of a real point-spread function.
  std::uniform_real_distribution<double> uniform(std::numeric_limits<double>::min(), 1.0);
  const double rayleigh_scale = 1.0 / std::sqrt(M_PI / 2.0);
  for (float& value : echo_) value = static_cast<float>(rayleigh_scale * std::sqrt(-2.0 * std::log(uniform(random_))));
  cv::Mat speckle(height, width, CV_32F, echo_.data());
  cv::GaussianBlur(speckle, speckle, cv::Size(0, 0), kSpeckleSigmaPx);
  for (int v = 0; v < height; ++v) {
    const double depth_m = v * geometry_.spacing_m;
    const double attenuation = std::exp(-scene_.attenuation_np_per_m * depth_m);
    for (int u = 0; u < width; ++u) {
      const Eigen::Vector3d point = liver_from_image * Eigen::Vector3d(u * geometry_.spacing_m, depth_m, 0.0);
      const double echo = echogenicity({point.x(), point.y(), point.z()});
      const std::size_t i = static_cast<std::size_t>(v) * geometry_.width_px + static_cast<std::size_t>(u);
      // Normalise the blurred speckle back to about unit mean (blur lowers its variance only).
      const double level = 255.0 * echo * attenuation * echo_[i];
      pixels[i] = static_cast<std::uint8_t>(std::clamp(std::lround(level), 0L, 255L));
    }
  }
  return truth(liver_from_image);
}

Eigen::Isometry3d plane_through_tumour(const BmodeGeometry& geometry, const BmodeScene& scene, double plane_offset_m,
                                       double depth_m) {
  // Image x along liver +x, image y (depth) along liver -z, image z = x cross y = +y.
  Eigen::Matrix3d rotation;
  rotation << 1, 0, 0, 0, 0, 1, 0, -1, 0;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = rotation;
  const Eigen::Vector3d centre(scene.tumour_centre_m[0], scene.tumour_centre_m[1] + plane_offset_m,
                               scene.tumour_centre_m[2]);
  const Eigen::Vector3d centre_in_image(0.5 * (geometry.width_px - 1) * geometry.spacing_m, depth_m, 0.0);
  pose.translation() = centre - rotation * centre_in_image;
  return pose;
}

}  // namespace nav::ultrasound
