// The synthetic B-mode device against its own geometry (analytic truth), and the tumour
// tracker against that truth: pixel and millimetre errors over a sweep, through DDS too.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <memory>
#include <vector>

#include "nav/ultrasound/bmode_device.hpp"
#include "nav/ultrasound/bmode_simulator.hpp"
#include "nav/ultrasound/tumour_tracker.hpp"
#include "ultrasound_device_link.hpp"

namespace nav::ultrasound {
namespace {

constexpr double kDepth_m = 0.04;

/// The mean of the pixels within `radius` of (u, v) (ring: between radius and 1.5 radius).
double mean_in_disc(const std::vector<std::uint8_t>& pixels, const BmodeGeometry& g, double u, double v, double radius,
                    bool ring) {
  double sum = 0.0;
  int count = 0;
  for (std::uint32_t y = 0; y < g.height_px; ++y) {
    for (std::uint32_t x = 0; x < g.width_px; ++x) {
      const double r = std::hypot(x - u, y - v);
      if (ring ? (r > radius && r < 1.5 * radius) : r < radius) {
        sum += pixels[y * g.width_px + x];
        ++count;
      }
    }
  }
  return sum / count;
}

TEST(BmodeSimulator, TruthMatchesThePlaneGeometry) {
  const BmodeGeometry geometry;
  const BmodeScene scene = default_bmode_scene();
  BmodeSimulator simulator(geometry, scene, 1);
  const BmodeTruth centred = simulator.truth(plane_through_tumour(geometry, scene, 0.0, kDepth_m));
  EXPECT_NEAR(centred.tumour_u_px, 127.5, 1e-9);
  EXPECT_NEAR(centred.tumour_v_px, kDepth_m / geometry.spacing_m, 1e-9);
  EXPECT_NEAR(centred.tumour_section_radius_px, 0.015 / geometry.spacing_m, 1e-9);
  // 9 mm off the centre: a section of radius sqrt(15^2 - 9^2) = 12 mm.
  const BmodeTruth offset = simulator.truth(plane_through_tumour(geometry, scene, 0.009, kDepth_m));
  EXPECT_NEAR(offset.tumour_section_radius_px * geometry.spacing_m, 0.012, 1e-12);
  EXPECT_NEAR(std::abs(offset.tumour_plane_distance_m), 0.009, 1e-12);
  EXPECT_FALSE(simulator.truth(plane_through_tumour(geometry, scene, 0.02, kDepth_m)).tumour_visible());
}

TEST(BmodeSimulator, TumourIsHypoechoicAndSpeckleIsSeeded) {
  const BmodeGeometry geometry;
  const BmodeScene scene = default_bmode_scene();
  const auto pose = plane_through_tumour(geometry, scene, 0.0, kDepth_m);
  std::vector<std::uint8_t> first(geometry.width_px * geometry.height_px), second(first.size()), other(first.size());
  BmodeSimulator a(geometry, scene, 7), b(geometry, scene, 7), c(geometry, scene, 8);
  const BmodeTruth truth = a.render(pose, first.data());
  b.render(pose, second.data());
  c.render(pose, other.data());
  EXPECT_EQ(first, second);
  EXPECT_NE(first, other);
  const double r = truth.tumour_section_radius_px;
  const double inside = mean_in_disc(first, geometry, truth.tumour_u_px, truth.tumour_v_px, 0.8 * r, false);
  const double around = mean_in_disc(first, geometry, truth.tumour_u_px, truth.tumour_v_px, 1.1 * r, true);
  std::printf("tumour mean %.1f, surroundings %.1f\n", inside, around);
  EXPECT_LT(inside, 0.4 * around);
}

TEST(TumourTracker, FindsTheTumourOverASweepWithinTwoPixelsAndAMillimetre) {
  const BmodeGeometry geometry;
  const BmodeScene scene = default_bmode_scene();
  BmodeSimulator simulator(geometry, scene, 11);
  TumourTracker tracker;
  Eigen::Isometry3d probe_from_image = Eigen::Isometry3d::Identity();
  probe_from_image.translation() = Eigen::Vector3d(-0.038, 0.002, 0.0);
  probe_from_image.linear() = Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitY()).toRotationMatrix();
  std::vector<std::uint8_t> pixels(geometry.width_px * geometry.height_px);
  double worst_px = 0.0, worst_mm = 0.0, lowest_confidence = 1.0;
  for (int step = 0; step <= 10; ++step) {
    const double offset_m = -0.010 + 0.002 * step;
    const double depth_m = 0.035 + 0.001 * step;
    const Eigen::Isometry3d liver_from_image = plane_through_tumour(geometry, scene, offset_m, depth_m);
    const BmodeTruth truth = simulator.render(liver_from_image, pixels.data());
    const TumourDetection found = tracker.update(pixels.data(), geometry.width_px, geometry.height_px);
    ASSERT_TRUE(found.found) << "step " << step;
    worst_px = std::max(worst_px, std::hypot(found.u_px - truth.tumour_u_px, found.v_px - truth.tumour_v_px));
    lowest_confidence = std::min(lowest_confidence, found.confidence);
    EXPECT_NEAR(found.radius_px, truth.tumour_section_radius_px, 0.1 * truth.tumour_section_radius_px);
    // Through the calibration and the tracked probe pose, against the section's true centre.
    const Eigen::Isometry3d liver_from_probe = liver_from_image * probe_from_image.inverse();
    const Eigen::Vector3d point = image_point_in_world(found.u_px, found.v_px, geometry.spacing_m, geometry.spacing_m,
                                                       probe_from_image, liver_from_probe);
    const Eigen::Vector3d section_centre =
        liver_from_image *
        Eigen::Vector3d(truth.tumour_u_px * geometry.spacing_m, truth.tumour_v_px * geometry.spacing_m, 0);
    worst_mm = std::max(worst_mm, 1e3 * (point - section_centre).norm());
  }
  std::printf("tumour centre: worst error %.2f px, %.3f mm; lowest confidence %.2f\n", worst_px, worst_mm,
              lowest_confidence);
  EXPECT_LT(worst_px, 2.0);
  EXPECT_LT(worst_mm, 0.6);
  EXPECT_GT(lowest_confidence, 0.5);
}

TEST(TumourTracker, ReportsNothingWhenThePlaneMissesTheTumour) {
  const BmodeGeometry geometry;
  const BmodeScene scene = default_bmode_scene();
  BmodeSimulator simulator(geometry, scene, 3);
  TumourTracker tracker;
  std::vector<std::uint8_t> pixels(geometry.width_px * geometry.height_px);
  simulator.render(plane_through_tumour(geometry, scene, 0.0, kDepth_m), pixels.data());
  ASSERT_TRUE(tracker.update(pixels.data(), geometry.width_px, geometry.height_px).found);
  simulator.render(plane_through_tumour(geometry, scene, 0.025, kDepth_m), pixels.data());
  const TumourDetection missed = tracker.update(pixels.data(), geometry.width_px, geometry.height_px);
  EXPECT_FALSE(missed.found);
}

TEST(BmodeDevice, PublishesFramesATrackerCanUseOverDds) {
  testing::DeviceLink link = testing::link_device(143);
  ASSERT_TRUE(link.ok);
  const BmodeGeometry geometry;
  const BmodeScene scene = default_bmode_scene();
  const Eigen::Isometry3d probe_from_image(Eigen::Translation3d(-0.038, 0.0, 0.0));
  BmodeDevice device(BmodeSimulator(geometry, scene, 5), probe_from_image, 2);
  const Eigen::Isometry3d liver_from_probe =
      plane_through_tumour(geometry, scene, 0.0, kDepth_m) * probe_from_image.inverse();
  // Frames and poses are best effort, as from a real scanner: the device publishes again
  // until the station has both (the first samples may leave before the station's side of
  // the match is complete).
  BmodeTruth truth;
  auto frame = std::make_unique<dds::UltrasoundFrame>();
  dds::ToolPose pose;
  bool received = false;
  for (int attempt = 0; attempt < 20 && !received; ++attempt) {
    bool published = false;
    truth = device.publish(*link.device, liver_from_probe, 1000 + attempt, published);
    ASSERT_TRUE(published);
    received = testing::next_frame(link, *frame) && link.poses->try_pop(pose);
  }
  ASSERT_TRUE(received) << "no frame and pose reached the station in 20 publications";
  EXPECT_NEAR(pose.position_m[2], liver_from_probe.translation().z(), 1e-15);
  TumourTracker tracker;
  const TumourDetection found = tracker.update(frame->pixels.data(), frame->width_px, frame->height_px);
  ASSERT_TRUE(found.found);
  EXPECT_LT(std::hypot(found.u_px - truth.tumour_u_px, found.v_px - truth.tumour_v_px), 2.0);
}

}  // namespace
}  // namespace nav::ultrasound
