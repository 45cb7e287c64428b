// The tracker-to-model registration: a simulated tracker publishes the model-frame poses of
// its tools in its own frame (through the reference marker's place and the URDF's
// reference-to-model joint), and the station's registration takes them back into the model
// frame: compared with the original poses, and with a registration that is told nothing of
// the reference (centimetres off). Also the URDF's joint as the scene loads it.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "nav/calibration/rigid_transform.hpp"
#include "nav/station/station_dds.hpp"
#include "nav/station/tracker_registration.hpp"
#include "nav/station/world_player.hpp"
#include "station/scene_text.hpp"

namespace nav::station {
namespace {

RigidPose pose_of(double x, double y, double z, double roll, double pitch, double yaw) {
  return {{x, y, z}, Eigen::Quaterniond(calibration::rpy_to_rotation({roll, pitch, yaw}))};
}

ToolIds tools_with_reference() {
  ToolIds tools;
  tools.reference = 7;
  return tools;
}

double angle_rad(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) { return a.angularDistance(b); }

TEST(TrackerRegistration, PosesPublishedInTheTrackersFrameComeBackInTheModelFrame) {
  const RigidPose reference_from_model = pose_of(0.02, -0.13, 0.07, 0.3, -0.2, 1.1);
  const RigidPose tracker_from_reference = pose_of(0.4, -0.25, 1.2, -0.5, 0.35, 2.4);
  const ToolIds tools = tools_with_reference();
  const SimulatedTracker tracker = simulated_tracker(tools, tracker_from_reference, reference_from_model);
  TrackerRegistration registration(reference_from_model, tools.reference);

  DeviceSample needle;
  needle.kind = SampleKind::needle_pose;
  needle.measured_ns = 5 * kNsPerMs;
  needle.pose = pose_of(-0.03, 0.09, 0.02, 0.1, 0.2, -0.3);
  DeviceSample respiratory;
  respiratory.kind = SampleKind::respiratory;
  respiratory.point_m = {0.01, 0.12, 0.08};

  // Before the reference's first pose nothing is used, and each pose is counted.
  EXPECT_FALSE(device_sample_of(tool_pose_of(needle, 1, 0, tracker), 0, 0, tools, registration));
  EXPECT_EQ(registration.unregistered_poses, 1);
  // The reference's own pose registers and is no sample of the loop.
  dds::ToolPose reference = tool_pose_of(respiratory, 2, 0, tracker);
  reference.tool_id = *tools.reference;
  reference.position_m = {tracker_from_reference.position_m[0], tracker_from_reference.position_m[1],
                          tracker_from_reference.position_m[2]};
  const Eigen::Quaterniond& q = tracker_from_reference.rotation;
  reference.orientation_wxyz = {q.w(), q.x(), q.y(), q.z()};
  EXPECT_FALSE(device_sample_of(reference, 0, 0, tools, registration));

  const dds::ToolPose published = tool_pose_of(needle, 3, 0, tracker);
  // On the wire the pose is the tracker's: far from the model-frame pose.
  EXPECT_GT((Eigen::Vector3d(published.position_m[0], published.position_m[1], published.position_m[2]) -
             needle.pose.position_m)
                .norm(),
            0.5);
  const std::optional<DeviceSample> back = device_sample_of(published, 0, 0, tools, registration);
  ASSERT_TRUE(back);
  EXPECT_EQ(back->kind, SampleKind::needle_pose);
  EXPECT_LT((back->pose.position_m - needle.pose.position_m).norm(), 1e-12);
  EXPECT_LT(angle_rad(back->pose.rotation, needle.pose.rotation), 1e-12);
  const std::optional<DeviceSample> breath =
      device_sample_of(tool_pose_of(respiratory, 4, 0, tracker), 0, 0, tools, registration);
  ASSERT_TRUE(breath);
  EXPECT_LT((breath->point_m - respiratory.point_m).norm(), 1e-12);
  EXPECT_EQ(registration.unregistered_poses, 1);

  // A tool of no role is no sample and no unregistered pose.
  dds::ToolPose stranger = published;
  stranger.tool_id = 42;
  EXPECT_FALSE(device_sample_of(stranger, 0, 0, tools, registration));
  EXPECT_EQ(registration.unregistered_poses, 1);

  // A station told of no reference takes the tracker's frame for the reference's: centimetres off.
  TrackerRegistration unaware(reference_from_model, std::nullopt);
  ToolIds without = tools;
  without.reference.reset();
  const std::optional<DeviceSample> wrong = device_sample_of(published, 0, 0, without, unaware);
  ASSERT_TRUE(wrong);
  EXPECT_GT((wrong->pose.position_m - needle.pose.position_m).norm(), 0.1);
}

TEST(TrackerRegistration, WithoutAReferenceTheUrdfJointAloneRegistersATrackerFixedToThePatient) {
  const RigidPose reference_from_model = pose_of(0.1, 0.0, -0.05, 0.0, 0.0, 0.5);
  const ToolIds tools;  // no reference
  const SimulatedTracker tracker = simulated_tracker(tools, pose_of(1, 2, 3, 0.1, 0.2, 0.3), reference_from_model);
  TrackerRegistration registration(reference_from_model, std::nullopt);
  DeviceSample probe;
  probe.kind = SampleKind::probe_pose;
  probe.pose = pose_of(0.02, 0.05, 0.09, -0.4, 0.1, 0.2);
  const std::optional<DeviceSample> back =
      device_sample_of(tool_pose_of(probe, 1, 0, tracker), 0, 0, tools, registration);
  ASSERT_TRUE(back);
  EXPECT_LT((back->pose.position_m - probe.pose.position_m).norm(), 1e-12);
  EXPECT_LT(angle_rad(back->pose.rotation, probe.pose.rotation), 1e-12);
  EXPECT_EQ(registration.unregistered_poses, 0);
}

TEST(TrackerRegistration, TheSceneTakesTheJointFromItsUrdfAndNamesAUrdfWithoutIt) {
  auto scene = load_scene(testing::example_scene_path("demo.yaml"));
  ASSERT_TRUE(scene.ok()) << scene.error().describe();
  auto identity = scene_reference_from_model(scene.value());
  ASSERT_TRUE(identity.ok()) << identity.error().describe();
  EXPECT_LT(identity.value().position_m.norm(), 1e-15);

  // The demo's URDF with its registration moved, as navtool calib register writes it.
  std::string urdf = testing::file_text(scene.value().frames.urdf_path);
  const std::string joint =
      "<joint name=\"reference_to_liver_model\" type=\"fixed\">\n    <parent link=\"reference_marker\"/><child "
      "link=\"liver_model\"/>\n    <origin xyz=\"0 0 0\" rpy=\"0 0 0\"/>";
  const std::string moved_joint =
      testing::edited(joint, "xyz=\"0 0 0\" rpy=\"0 0 0\"", "xyz=\"0.01 -0.2 0.3\" rpy=\"0 0 1.5707963267948966\"");
  urdf = testing::edited(urdf, joint, moved_joint);
  const std::string path = testing::temporary_path("registered.urdf");
  std::ofstream(path) << urdf;
  scene.value().frames.urdf_path = path;
  auto moved = scene_reference_from_model(scene.value());
  ASSERT_TRUE(moved.ok()) << moved.error().describe();
  EXPECT_LT((moved.value().position_m - Eigen::Vector3d(0.01, -0.2, 0.3)).norm(), 1e-12);
  EXPECT_LT((moved.value().rotation * Eigen::Vector3d::UnitX() - Eigen::Vector3d::UnitY()).norm(), 1e-12);

  // A URDF without the joint: refused at the scene's frames.urdf, naming the chain.
  std::ofstream(path) << testing::edited(testing::edited(urdf, moved_joint + "\n  </joint>", ""),
                                         "<link name=\"liver_model\"/>", "");
  auto missing = scene_reference_from_model(scene.value());
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.error().describe().find("reference_marker to liver_model"), std::string::npos)
      << missing.error().describe();
  EXPECT_NE(missing.error().describe().find("frames.urdf"), std::string::npos) << missing.error().describe();
}

}  // namespace
}  // namespace nav::station
