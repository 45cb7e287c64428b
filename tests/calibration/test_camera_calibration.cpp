// Camera intrinsics (Zhang) from synthetic AprilTag board frames: tags rendered through a
// known camera, detected, their corners fed to the calibration; fx, fy within 0.5 %, the
// principal point within 2 px; through a known lens distortion, k1, k2, p1, p2 recovered
// too. Degenerate view sets are refused.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "nav/calibration/camera_calibration.hpp"
#include "nav/trackers/apriltag_tracker.hpp"
#include "support/run_command.hpp"
#include "support/test_data.hpp"

namespace nav::calibration {
namespace {

constexpr double kTagSize_m = 0.03;
constexpr double kPitch_m = 0.04;
const trackers::CameraIntrinsics kTruth{610.0, 605.0, 322.0, 236.5};
const calibration::LensDistortion kLens{-0.22, 0.09, 0.0011, -0.0008, 0.0};

/// Board frame from tag `id` (4 x 3 grid, ids 0..11, board centred).
Eigen::Isometry3d board_from_tag(int id) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(((id % 4) - 1.5) * kPitch_m, ((id / 4) - 1.0) * kPitch_m, 0.0);
  return pose;
}

Eigen::Isometry3d view_pose(double rx_deg, double ry_deg, const Eigen::Vector3d& t_m) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = (Eigen::AngleAxisd(rx_deg * M_PI / 180.0, Eigen::Vector3d::UnitX()) *
                   Eigen::AngleAxisd(ry_deg * M_PI / 180.0, Eigen::Vector3d::UnitY()))
                      .toRotationMatrix();
  pose.translation() = t_m;
  return pose;
}

/// Renders the board at `camera_from_board`, detects it, and returns the corner view.
PlanarView board_view(const trackers::AprilTagTracker& detector, const Eigen::Isometry3d& camera_from_board,
                      std::uint64_t seed, const trackers::CameraIntrinsics& camera = kTruth) {
  std::vector<trackers::TagRendering> tags;
  for (int id = 0; id < 12; ++id) tags.push_back({id, camera_from_board * board_from_tag(id)});
  const trackers::GrayImage image = trackers::render_tags(tags, kTagSize_m, camera, 640, 480, 2.0, seed);
  PlanarView view;
  for (const trackers::TagObservation& seen : detector.detect(image)) {
    for (int k = 0; k < 4; ++k) {
      const Eigen::Vector3d corner = board_from_tag(seen.id) * trackers::tag_corner(k, kTagSize_m);
      view.board_points_m.emplace_back(corner.x(), corner.y());
      view.image_points_px.push_back(seen.corners_px[k]);
    }
  }
  return view;
}

TEST(CameraCalibration, IntrinsicsFromAprilTagBoardFrames) {
  // The detector's own intrinsics play no part in the corners.
  auto detector = trackers::AprilTagTracker::create(trackers::CameraIntrinsics{}, kTagSize_m, {});
  ASSERT_TRUE(detector.ok());
  const std::vector<Eigen::Isometry3d> poses{
      view_pose(25, 0, {0.0, 0.0, 0.35}),     view_pose(-25, 10, {0.02, 0.01, 0.33}),
      view_pose(0, 30, {-0.02, 0.0, 0.36}),   view_pose(10, -30, {0.01, -0.02, 0.3}),
      view_pose(-20, -20, {0.05, 0.03, 0.4}), view_pose(30, 25, {-0.04, -0.03, 0.38})};
  std::vector<PlanarView> views;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    views.push_back(board_view(*detector.value(), poses[i], 100 + i));
    ASSERT_GE(views.back().board_points_m.size(), 40u) << "view " << i;
  }
  auto result = calibrate_camera(views);
  ASSERT_TRUE(result.ok()) << result.error().describe();
  const CameraCalibration& c = result.value();
  std::printf("camera: fx %.2f (%.2f) fy %.2f (%.2f) cx %.2f (%.2f) cy %.2f (%.2f) px, RMS %.3f px, %zu views\n",
              c.fx_px, kTruth.fx_px, c.fy_px, kTruth.fy_px, c.cx_px, kTruth.cx_px, c.cy_px, kTruth.cy_px,
              c.rms_reprojection_px, views.size());
  EXPECT_NEAR(c.fx_px / kTruth.fx_px, 1.0, 0.005);
  EXPECT_NEAR(c.fy_px / kTruth.fy_px, 1.0, 0.005);
  EXPECT_NEAR(c.cx_px, kTruth.cx_px, 2.0);
  EXPECT_NEAR(c.cy_px, kTruth.cy_px, 2.0);
  EXPECT_LT(c.rms_reprojection_px, 0.3);
  EXPECT_LT((c.camera_from_board[0].translation() - poses[0].translation()).norm(), 2e-3);
  // No lens distortion in these frames: the estimated one stays small.
  EXPECT_LT(std::abs(c.distortion.k1), 0.02);
  EXPECT_LT(std::abs(c.distortion.p1) + std::abs(c.distortion.p2), 3e-3);
}

TEST(CameraCalibration, LensDistortionFromAprilTagBoardFrames) {
  trackers::CameraIntrinsics camera = kTruth;
  camera.distortion = kLens;
  auto detector = trackers::AprilTagTracker::create(trackers::CameraIntrinsics{}, kTagSize_m, {});
  ASSERT_TRUE(detector.ok());
  // Boards tilted and moved towards the image's edges and corners, where the lens acts most.
  const std::vector<Eigen::Isometry3d> poses{
      view_pose(25, 0, {0.0, 0.0, 0.33}),        view_pose(-25, 10, {0.08, 0.06, 0.33}),
      view_pose(0, 30, {-0.09, 0.05, 0.34}),     view_pose(10, -30, {0.08, -0.06, 0.3}),
      view_pose(-20, -20, {-0.08, -0.06, 0.33}), view_pose(30, 25, {0.0, -0.07, 0.3}),
      view_pose(-15, 20, {0.10, 0.0, 0.32}),     view_pose(20, -15, {-0.10, 0.01, 0.32})};
  std::vector<PlanarView> views;
  for (std::size_t i = 0; i < poses.size(); ++i) {
    views.push_back(board_view(*detector.value(), poses[i], 300 + i, camera));
    ASSERT_GE(views.back().board_points_m.size(), 24u) << "view " << i;  // some tags may leave the image
  }
  auto result = calibrate_camera(views);
  ASSERT_TRUE(result.ok()) << result.error().describe();
  const CameraCalibration& c = result.value();
  const LensDistortion& d = c.distortion;
  std::printf("camera: fx %.2f (%.2f) fy %.2f (%.2f) cx %.2f (%.2f) cy %.2f (%.2f) px, RMS %.3f px\n", c.fx_px,
              kTruth.fx_px, c.fy_px, kTruth.fy_px, c.cx_px, kTruth.cx_px, c.cy_px, kTruth.cy_px, c.rms_reprojection_px);
  std::printf("lens: k1 %.4f (%.4f) k2 %.4f (%.4f) p1 %.5f (%.5f) p2 %.5f (%.5f)\n", d.k1, kLens.k1, d.k2, kLens.k2,
              d.p1, kLens.p1, d.p2, kLens.p2);
  EXPECT_NEAR(c.fx_px / kTruth.fx_px, 1.0, 0.005);
  EXPECT_NEAR(c.fy_px / kTruth.fy_px, 1.0, 0.005);
  EXPECT_NEAR(c.cx_px, kTruth.cx_px, 2.0);
  EXPECT_NEAR(c.cy_px, kTruth.cy_px, 2.0);
  EXPECT_NEAR(d.k1, kLens.k1, 0.005);
  EXPECT_NEAR(d.k2, kLens.k2, 0.02);
  EXPECT_NEAR(d.p1, kLens.p1, 3e-4);
  EXPECT_NEAR(d.p2, kLens.p2, 3e-4);
  EXPECT_EQ(d.k3, 0.0);  // not estimated by default
  EXPECT_LT(c.rms_reprojection_px, 0.5);
  // Without the lens model the same corners fit far worse.
  auto pinhole = calibrate_camera(views, {.estimate_distortion = false});
  ASSERT_TRUE(pinhole.ok());
  std::printf("pinhole only: RMS %.3f px\n", pinhole.value().rms_reprojection_px);
  EXPECT_GT(pinhole.value().rms_reprojection_px, 4.0 * c.rms_reprojection_px);
}

TEST(CameraCalibration, NavtoolCalibCameraReadsAnImageFolder) {
  const std::string folder = nav::testing::temporary_path("calib_camera_frames");
  std::filesystem::remove_all(folder);
  std::filesystem::create_directories(folder);
  const std::vector<Eigen::Isometry3d> poses{view_pose(25, 0, {0.0, 0.0, 0.35}), view_pose(-25, 10, {0.02, 0.01, 0.33}),
                                             view_pose(0, 30, {-0.02, 0.0, 0.36}),
                                             view_pose(10, -30, {0.01, -0.02, 0.3})};
  for (std::size_t i = 0; i < poses.size(); ++i) {
    std::vector<trackers::TagRendering> tags;
    for (int id = 0; id < 12; ++id) tags.push_back({id, poses[i] * board_from_tag(id)});
    const std::string file = folder + "/view_" + std::to_string(i) + ".pgm";
    ASSERT_TRUE(
        trackers::write_pgm(file, trackers::render_tags(tags, kTagSize_m, kTruth, 640, 480, 2.0, 200 + i)).ok());
  }
  const std::string out = nav::testing::temporary_path("calib_camera_intrinsics.txt");
  const auto run =
      nav::testing::run_command(nav::testing::executable_path("navtool") + " calib camera --images " + folder +
                                " --tag-size 0.03 --pitch 0.04 --cols 4 --rows 3 --out " + out + " 2>&1");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  std::ifstream intrinsics(out);
  std::string header;
  std::getline(intrinsics, header);
  double fx = 0.0, fy = 0.0, cx = 0.0, cy = 0.0, k1 = 1.0, k2 = 1.0, p1 = 1.0, p2 = 1.0, k3 = 1.0, rms = -1.0;
  intrinsics >> fx >> fy >> cx >> cy >> k1 >> k2 >> p1 >> p2 >> k3 >> rms;
  ASSERT_TRUE(intrinsics) << "expected fx fy cx cy k1 k2 p1 p2 k3 rms in " << out;
  EXPECT_NEAR(fx / kTruth.fx_px, 1.0, 0.005);
  EXPECT_NEAR(cy, kTruth.cy_px, 2.0);
  EXPECT_LT(std::abs(k1), 0.05);  // rendered without distortion
  EXPECT_EQ(k3, 0.0);
  EXPECT_GT(rms, 0.0);
  EXPECT_LT(rms, 0.5);
  EXPECT_NE(run.output.find("k1 "), std::string::npos) << run.output;
  const auto bad =
      nav::testing::run_command(nav::testing::executable_path("navtool") + " calib camera --images " + folder +
                                " --tag-size zero --pitch 0.04 --cols 4 --rows 3 --out " + out + " 2>&1");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.output.find("--tag-size"), std::string::npos) << bad.output;
}

TEST(CameraCalibration, DegenerateViewsAreRefused) {
  PlanarView view;
  for (int i = 0; i < 6; ++i) {
    view.board_points_m.emplace_back(0.01 * i, 0.0);  // collinear
    view.image_points_px.emplace_back(10.0 * i, 5.0);
  }
  auto collinear = calibrate_camera({view, view, view});
  ASSERT_FALSE(collinear.ok());
  EXPECT_NE(collinear.error().message.find("collinear"), std::string::npos);
  EXPECT_FALSE(calibrate_camera({view, view}).ok());  // too few views
  // Three fronto-parallel views: the focal length is not observable.
  std::vector<PlanarView> parallel;
  for (int v = 0; v < 3; ++v) {
    PlanarView flat;
    for (int i = 0; i < 9; ++i) {
      const Eigen::Vector2d b(0.02 * (i % 3), 0.02 * (i / 3));
      flat.board_points_m.push_back(b);
      flat.image_points_px.push_back(Eigen::Vector2d(320.0, 240.0) + (2000.0 + 100.0 * v) * b);
    }
    parallel.push_back(flat);
  }
  EXPECT_FALSE(calibrate_camera(parallel).ok());
}

}  // namespace
}  // namespace nav::calibration
