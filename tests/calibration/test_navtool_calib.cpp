// navtool calib pivot / handeye / register end to end: recorded CSV in, station URDF out with
// the calibrated joint, its date and residual; bad input named with file and line.
#include <gtest/gtest.h>

#include <fstream>

#include "calibration_truth.hpp"
#include "nav/calibration/frame_tree.hpp"
#include "nav/calibration/pose_csv.hpp"
#include "support/run_command.hpp"
#include "support/test_data.hpp"

namespace nav::calibration {
namespace {

using namespace nav::calibration::testing;
using nav::testing::executable_path;
using nav::testing::run_command;
using nav::testing::temporary_path;

TEST(NavtoolCalib, PivotWritesTheTipJoint) {
  std::mt19937_64 rng(41);
  const Eigen::Vector3d tip_m(0.002, 0.001, 0.17);
  std::vector<RecordedPose> poses;
  for (int i = 0; i < 100; ++i) {
    const Eigen::Matrix3d rotation = random_rotation(rng, 0.5);
    const Eigen::Vector3d position = Eigen::Vector3d(0.0, 0.0, -1.0) - rotation * tip_m + gaussian_vector(rng, 0.05e-3);
    poses.push_back({i * kNsPerMs * 20, "needle", transform(rotation, position)});
    poses.push_back({i * kNsPerMs * 20 + 1, "probe", Transform::Identity()});  // another tool, ignored
  }
  const std::string csv = temporary_path("calib_pivot_poses.csv");
  const std::string out = temporary_path("calib_pivot_station.urdf");
  ASSERT_TRUE(write_pose_csv(csv, poses).ok());
  const auto run = run_command(executable_path("navtool") + " calib pivot --poses " + csv + " --tool needle --urdf " +
                               kStationUrdf + " --out " + out + " 2>&1");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  auto tree = FrameTree::load(out);
  ASSERT_TRUE(tree.ok()) << tree.error().describe();
  const FrameJoint* joint = tree.value().joint("needle_base_to_tip");
  ASSERT_TRUE(joint->record.has_value());
  EXPECT_LT((joint->parent_from_child.translation() - tip_m).norm(), 0.1e-3);
  EXPECT_NEAR(joint->record->residual_m, std::sqrt(3.0) * 0.05e-3, 0.02e-3);
}

TEST(NavtoolCalib, HandEyeWritesTheCameraJoint) {
  std::mt19937_64 rng(42);
  const Transform truth = transform(random_rotation(rng, 2.0), {0.02, 0.03, 0.05});
  const Transform tracker_from_target = transform(random_rotation(rng, 1.0), {0.0, 0.1, -0.9});
  std::vector<RecordedPose> markers, cameras;
  for (int i = 0; i < 12; ++i) {
    const Transform marker = transform(random_rotation(rng, 0.7), gaussian_vector(rng, 0.1));
    markers.push_back({i * kNsPerMs, "camera_marker", marker});
    cameras.push_back({i * kNsPerMs, "target", (marker * truth).inverse() * tracker_from_target});
  }
  const std::string marker_csv = temporary_path("calib_handeye_markers.csv");
  const std::string camera_csv = temporary_path("calib_handeye_cameras.csv");
  const std::string out = temporary_path("calib_handeye_station.urdf");
  ASSERT_TRUE(write_pose_csv(marker_csv, markers).ok());
  ASSERT_TRUE(write_pose_csv(camera_csv, cameras).ok());
  const auto run = run_command(executable_path("navtool") + " calib handeye --marker-poses " + marker_csv +
                               " --camera-poses " + camera_csv + " --urdf " + kStationUrdf + " --out " + out + " 2>&1");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  auto tree = FrameTree::load(out);
  ASSERT_TRUE(tree.ok());
  EXPECT_TRUE(tree.value().joint("camera_marker_to_camera")->parent_from_child.isApprox(truth, 1e-9));
}

TEST(NavtoolCalib, RegisterWritesTheModelJoint) {
  std::mt19937_64 rng(43);
  const Transform truth = transform(random_rotation(rng, 1.0), {0.1, -0.05, 0.02});
  std::ofstream model(temporary_path("calib_register_model.csv")),
      tracked(temporary_path("calib_register_tracked.csv"));
  model << "# x_m,y_m,z_m\n";
  for (const Eigen::Vector3d& p : {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0.1, 0, 0.01),
                                   Eigen::Vector3d(0, 0.1, 0.02), Eigen::Vector3d(0.05, 0.05, 0.08)}) {
    const Eigen::Vector3d q = truth * p;
    model << p.x() << "," << p.y() << "," << p.z() << "\n";
    tracked.precision(17);
    tracked << q.x() << "," << q.y() << "," << q.z() << "\n";
  }
  model.close();
  tracked.close();
  const std::string out = temporary_path("calib_register_station.urdf");
  const auto run =
      run_command(executable_path("navtool") + " calib register --model-points " +
                  temporary_path("calib_register_model.csv") + " --tracked-points " +
                  temporary_path("calib_register_tracked.csv") + " --urdf " + kStationUrdf + " --out " + out + " 2>&1");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  auto tree = FrameTree::load(out);
  ASSERT_TRUE(tree.ok());
  EXPECT_TRUE(tree.value().joint("reference_to_liver_model")->parent_from_child.isApprox(truth, 1e-9));
}

TEST(NavtoolCalib, BadInputIsNamed) {
  const std::string csv = temporary_path("calib_bad_poses.csv");
  std::ofstream(csv) << "# header\n0.0,needle,0,0,0,1,0,0,0\n0.1,needle,0,zero,0,1,0,0,0\n";
  const auto run = run_command(executable_path("navtool") + " calib pivot --poses " + csv + " 2>&1");
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_NE(run.output.find(csv + ":3: column 4: not a finite number"), std::string::npos) << run.output;
  std::ofstream(csv) << "0.0,needle,0,0,0,1,0,0,0\n";
  const auto few = run_command(executable_path("navtool") + " calib pivot --poses " + csv + " 2>&1");
  EXPECT_EQ(few.exit_code, 2);
  EXPECT_NE(few.output.find("too few poses"), std::string::npos) << few.output;
}

}  // namespace
}  // namespace nav::calibration
