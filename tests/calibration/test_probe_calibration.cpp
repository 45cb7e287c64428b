// Probe spatial calibration: the N-wire geometry and phantom definition against hand
// computation, the point-target calibration against synthetic truth (<= 1 mm), and the
// N-wire calibration of the real fCal 2.0 recording against PLUS's regression baseline for it:
// a lower validation error by PLUS's statistic, the image mapped within 0.3 mm of PLUS's map.
#include <gtest/gtest.h>

#include <cstdio>
#include <random>
#include <vector>

#include "calibration_truth.hpp"
#include "nav/calibration/nwire_calibration.hpp"
#include "nav/calibration/nwire_phantom.hpp"
#include "nav/calibration/probe_calibration.hpp"
#include "nav/ultrasound/plus_sequence.hpp"
#include "nav/ultrasound/plus_transform.hpp"
#include "support/test_data.hpp"

namespace nav::calibration {
namespace {

using testing::gaussian_vector;
using testing::random_rotation;
using testing::transform;

std::string plus_path(const std::string& name) { return nav::testing::shared_data_path("plus/" + name); }

/// The first fCal 2.0 pattern (mm): wires at x = 30 and 60 along y, the diagonal 55 -> 35.
NWirePattern fcal_top_pattern() {
  NWirePattern pattern;
  pattern[0] = {1e-3 * Eigen::Vector3d(30, 0, 20), 1e-3 * Eigen::Vector3d(30, 40, 20)};
  pattern[1] = {1e-3 * Eigen::Vector3d(55, 0, 20), 1e-3 * Eigen::Vector3d(35, 40, 20)};
  pattern[2] = {1e-3 * Eigen::Vector3d(60, 0, 20), 1e-3 * Eigen::Vector3d(60, 40, 20)};
  return pattern;
}

/// The largest distance, over the corners and centre of a 820 x 616 image, between the probe
/// points of two calibrations.
double worst_image_error_m(const ProbeCalibration& a, const ProbeCalibration& b) {
  double worst = 0.0;
  for (const Eigen::Vector2d& pixel : {Eigen::Vector2d(0, 0), Eigen::Vector2d(819, 0), Eigen::Vector2d(0, 615),
                                       Eigen::Vector2d(819, 615), Eigen::Vector2d(410, 308)}) {
    worst = std::max(worst, (probe_point(a, pixel) - probe_point(b, pixel)).norm());
  }
  return worst;
}

TEST(NWirePhantom, MiddleWirePointFollowsTheDotRatio) {
  // Dots half way: across the wires x = 45 mm, so the diagonal is half way along: y = 20 mm.
  const Eigen::Vector3d half = middle_wire_point(fcal_top_pattern(), {0, 0}, {50, 1}, {100, 2});
  EXPECT_LT((half - 1e-3 * Eigen::Vector3d(45, 20, 20)).norm(), 1e-12);
  // A quarter: x = 37.5 mm, (55 - 37.5) / 20 * 40 = 35 mm along.
  const Eigen::Vector3d quarter = middle_wire_point(fcal_top_pattern(), {10, 10}, {35, 10}, {110, 10});
  EXPECT_LT((quarter - 1e-3 * Eigen::Vector3d(37.5, 35, 20)).norm(), 1e-12);
}

TEST(NWirePhantom, ReadsTheFcalDefinitionAndRejectsBrokenOnes) {
  const std::string path = plus_path("PlusDeviceSet_fCal_Sim_SpatialCalibration_2.0.xml");
  if (nav::testing::file_exists(path)) {
    const auto phantom = load_nwire_phantom(path);
    ASSERT_TRUE(phantom.ok()) << phantom.error().describe();
    ASSERT_EQ(phantom.value().patterns.size(), 3u);
    EXPECT_LT((phantom.value().patterns[0][1].front_m - 1e-3 * Eigen::Vector3d(55, 0, 20)).norm(), 1e-15);
    EXPECT_LT((phantom.value().patterns[2][1].back_m - 1e-3 * Eigen::Vector3d(40, 40, 0)).norm(), 1e-15);
    EXPECT_NEAR(phantom.value().reference_from_phantom.translation().x(), 0.0156642, 1e-12);
    EXPECT_NEAR(phantom.value().reference_from_phantom.linear()(1, 0), -0.999834, 1e-12);
  }
  const std::string wires =
      "<PhantomDefinition>\n<Pattern Type=\"NWire\">\n"
      "<Wire EndPointFront=\"0 0 0\" EndPointBack=\"0 40 0\" />\n"
      "<Wire EndPointFront=\"20 0 0\" EndPointBack=\"5 40 0\" />\n"
      "<Wire EndPointFront=\"30 0 0\" EndPointBack=\"30 40\" />\n</Pattern>\n</PhantomDefinition>\n";
  const auto broken = parse_nwire_phantom(wires, "phantom.xml");
  ASSERT_FALSE(broken.ok());
  EXPECT_EQ(broken.error().line, 5);
  EXPECT_EQ(broken.error().field, "Wire");
  std::string fixed = wires;
  fixed.replace(fixed.find("30 40\""), 6, "30 40 0\"");
  const auto no_registration = parse_nwire_phantom(fixed, "phantom.xml");
  ASSERT_FALSE(no_registration.ok());
  EXPECT_EQ(no_registration.error().field, "CoordinateDefinitions");
}

TEST(ProbeCalibration, PointTargetMeetsOneMillimetreWithNoise) {
  std::mt19937_64 rng(42);
  ProbeCalibration truth;
  truth.probe_from_image = transform(random_rotation(rng, 3.0), Eigen::Vector3d(0.02, -0.03, 0.05));
  truth.spacing_m = {0.08e-3, 0.075e-3};
  const Eigen::Vector3d target(0.10, 0.20, -0.05);
  std::vector<TargetSighting> sightings;
  std::normal_distribution<double> pixel_noise(0.0, 1.0);
  std::uniform_real_distribution<double> u(100, 720), v(80, 540);
  while (sightings.size() < 40) {
    // A probe pose that puts the target at a random pixel: choose the pixel and rotation,
    // then place the probe so that pixel's point lands on the target.
    const Eigen::Vector2d pixel(u(rng), v(rng));
    const Eigen::Matrix3d rotation = random_rotation(rng, 0.6);
    const Eigen::Vector3d in_probe = probe_point(truth, pixel);
    Transform tracker_from_probe = transform(rotation, target - rotation * in_probe);
    tracker_from_probe.translation() += gaussian_vector(rng, 0.1e-3);  // tracker noise
    sightings.push_back({tracker_from_probe, pixel + Eigen::Vector2d(pixel_noise(rng), pixel_noise(rng))});
  }
  const auto result = point_target_calibration(sightings);
  ASSERT_TRUE(result.ok()) << result.error().describe();
  const double error_m = worst_image_error_m(result.value().calibration, truth);
  std::printf("point target: worst image error %.3f mm, target error %.3f mm, rms %.3f mm\n", 1e3 * error_m,
              1e3 * (result.value().target_in_tracker_m - target).norm(),
              1e3 * result.value().calibration.rms_residual_m);
  EXPECT_LT(error_m, 1e-3);
  EXPECT_NEAR(result.value().calibration.spacing_m.x(), truth.spacing_m.x(), 0.002e-3);
}

TEST(ProbeCalibration, DegenerateInputIsAnError) {
  std::vector<TargetSighting> same_pose(10);
  for (std::size_t i = 0; i < same_pose.size(); ++i) same_pose[i].pixel = {10.0 * i, 5.0 * i * i};
  const auto stuck = point_target_calibration(same_pose);
  ASSERT_FALSE(stuck.ok());
  EXPECT_NE(stuck.error().message.find("variety"), std::string::npos);
  EXPECT_FALSE(point_target_calibration(std::vector<TargetSighting>(3)).ok());
  std::vector<ImageProbePoint> collinear;
  for (int i = 0; i < 10; ++i) collinear.push_back({{1.0 * i, 2.0 * i}, {0.001 * i, 0.0, 0.0}});
  const auto line = fit_probe_calibration(collinear);
  ASSERT_FALSE(line.ok());
  EXPECT_NE(line.error().message.find("collinear"), std::string::npos);
}

/// The tracked frames of a PLUS recording (its pixels stay in `sequence`).
std::vector<TrackedImage> tracked_images(const ultrasound::PlusSequence& sequence) {
  std::vector<TrackedImage> frames;
  const auto* probe = sequence.find_transform("ProbeToTracker");
  const auto* reference = sequence.find_transform("ReferenceToTracker");
  for (std::size_t i = 0; i < sequence.frames_read; ++i) {
    if (!probe->valid[i] || !reference->valid[i] || !sequence.image_valid[i]) continue;
    frames.push_back({sequence.frame(i), static_cast<int>(sequence.width_px), static_cast<int>(sequence.height_px),
                      ultrasound::rigid_transform_m(probe->matrices_mm[i]),
                      ultrasound::rigid_transform_m(reference->matrices_mm[i])});
  }
  return frames;
}

/// PLUS's own regression baseline for these two recordings: its ProbeCalibration tool's test
/// vtkFreehandCalibration3NWiresfCal20Test (PlusLib src/PlusCalibration/Testing/CMakeLists.txt)
/// compares with PlusLibData's TestImages/FreehandCalibration3NWires_fCal2.0.results.xml
/// (commit 51dcbb76, the one these files come from): the validation ReprojectionError3D mean of
/// the lowest 95 %, and the ImageToProbe matrix (pixels to millimetres).
constexpr double kPlusValidationMeanMm = 0.539932;
constexpr double kPlusImageToProbe[3][4] = {{-0.000519165, 0.0744587, 0.000837223, 11.2137},
                                            {-0.0803067, -6.68987e-005, 0.00174527, 48.4162},
                                            {0.00181709, -0.000804192, 0.0773718, -0.398993}};

/// The largest distance (mm) over a grid across a width x height image between the points
/// `calibration` and PLUS's baseline give a pixel in the probe frame.
double largest_distance_from_plus_mm(const ProbeCalibration& calibration, int width, int height) {
  double largest = 0.0;
  for (int i = 0; i <= 20; ++i) {
    for (int j = 0; j <= 20; ++j) {
      const Eigen::Vector2d pixel(i * (width - 1) / 20.0, j * (height - 1) / 20.0);
      Eigen::Vector3d theirs_mm;
      for (int r = 0; r < 3; ++r)
        theirs_mm[r] =
            kPlusImageToProbe[r][0] * pixel.x() + kPlusImageToProbe[r][1] * pixel.y() + kPlusImageToProbe[r][3];
      largest = std::max(largest, (1e3 * probe_point(calibration, pixel) - theirs_mm).norm());
    }
  }
  return largest;
}

TEST(NWireCalibration, RealFcalRecordingBeatsPlusOnTheIndependentSet) {
  const std::string xml = plus_path("PlusDeviceSet_fCal_Sim_SpatialCalibration_2.0.xml");
  const std::string calibration_file = plus_path("fCal_Test_Calibration_3NWires_fCal2.0.igs.mha");
  const std::string validation_file = plus_path("fCal_Test_Validation_3NWires_fCal2.0.igs.mha");
  NAV_REQUIRE_SHARED_DATA(calibration_file);
  NAV_REQUIRE_SHARED_DATA(validation_file);
  const auto phantom = load_nwire_phantom(xml);
  ASSERT_TRUE(phantom.ok()) << phantom.error().describe();
  const auto recording = ultrasound::read_plus_sequence(calibration_file);
  ASSERT_TRUE(recording.ok()) << recording.error().describe();
  const auto result = nwire_calibration(tracked_images(recording.value()), phantom.value());
  ASSERT_TRUE(result.ok()) << result.error().describe();
  const ProbeCalibration& calibration = result.value().calibration;

  const auto validation = ultrasound::read_plus_sequence(validation_file);
  ASSERT_TRUE(validation.ok());
  const NWirePoints points =
      nwire_points(tracked_images(validation.value()), phantom.value(), result.value().correspondence);
  const ProbeValidation check = validate_probe_calibration(calibration, points.points);
  const double from_plus_mm = largest_distance_from_plus_mm(calibration, 820, 616);
  std::printf(
      "fCal 2.0: %zu/%zu frames segmented, %zu points (%zu outliers), rms %.3f mm, spacing %.4f x %.4f mm, "
      "uncertainty %.3f mm over the image (%zu bootstrap fits)\n",
      result.value().frames_segmented, result.value().frames_total, calibration.points, calibration.outliers,
      1e3 * calibration.rms_residual_m, 1e3 * calibration.spacing_m.x(), 1e3 * calibration.spacing_m.y(),
      1e3 * result.value().uncertainty_m, result.value().bootstrap_fits);
  std::printf(
      "validation: %zu/%zu frames, %zu points, mean %.3f rms %.3f max %.3f mm; PLUS's statistic (lowest 95 %%) "
      "mean %.4f sd %.4f mm, PLUS's baseline %.4f mm; largest distance from PLUS's map over the image %.3f mm\n",
      points.frames_segmented, points.frames_total, check.points, 1e3 * check.mean_error_m, 1e3 * check.rms_error_m,
      1e3 * check.max_error_m, 1e3 * check.lowest95_mean_error_m, 1e3 * check.lowest95_sd_error_m,
      kPlusValidationMeanMm, from_plus_mm);
  EXPECT_GT(result.value().frames_segmented, 9 * result.value().frames_total / 10);
  EXPECT_EQ(points.frames_segmented, points.frames_total);
  EXPECT_LT(calibration.rms_residual_m, 1.0e-3);
  EXPECT_LT(1e3 * check.lowest95_mean_error_m, kPlusValidationMeanMm);
  EXPECT_LT(check.max_error_m, 2.5e-3);
  EXPECT_LT(from_plus_mm, 0.3);
  EXPECT_GT(result.value().uncertainty_m, 0.01e-3);
  EXPECT_LT(result.value().uncertainty_m, 0.5e-3);
  // The scanner's nominal spacing for this probe (the XML's TransducerOriginPixel scale).
  EXPECT_NEAR(calibration.spacing_m.x(), 0.0796e-3, 0.002e-3);
  EXPECT_NEAR(calibration.spacing_m.y(), 0.0745e-3, 0.002e-3);
}

TEST(NWireCalibration, PhantomNotInTheImagesIsAnError) {
  std::vector<std::uint8_t> blank(820 * 616, 0);
  std::vector<TrackedImage> frames(20,
                                   TrackedImage{blank.data(), 820, 616, Transform::Identity(), Transform::Identity()});
  NWirePhantom phantom;
  phantom.patterns.push_back(fcal_top_pattern());
  const auto result = nwire_calibration(frames, phantom);
  ASSERT_FALSE(result.ok());
  EXPECT_NE(result.error().message.find("found in 0 of 20 frames"), std::string::npos);
}

}  // namespace
}  // namespace nav::calibration
