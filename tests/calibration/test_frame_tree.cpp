// The station's frame tree from its URDF: static chains, tracked joints interpolated with
// SLERP, errors outside the buffered span and for bad files, calibrations written and read back.
#include <gtest/gtest.h>

#include <fstream>

#include "nav/calibration/frame_tree.hpp"
#include "support/test_data.hpp"

namespace nav::calibration {
namespace {

using nav::testing::temporary_path;

const std::string kStationUrdf = std::string(NAV_TEST_DATA_DIR) + "/../../calibration/urdf/station.urdf";

FrameTree load_station() {
  auto tree = FrameTree::load(kStationUrdf);
  EXPECT_TRUE(tree.ok()) << (tree.ok() ? "" : tree.error().describe());
  return std::move(tree).value();
}

Transform pose(double angle_rad, const Eigen::Vector3d& axis, const Eigen::Vector3d& t_m) {
  return make_transform(Eigen::Quaterniond(Eigen::AngleAxisd(angle_rad, axis.normalized())), t_m);
}

TEST(FrameTree, LoadsTheStationFrames) {
  const FrameTree tree = load_station();
  const std::vector<std::string> expected{"camera",           "camera_marker", "image_plane", "liver_model",
                                          "needle_base",      "needle_marker", "needle_tip",  "probe_marker",
                                          "reference_marker", "tracker"};
  EXPECT_EQ(tree.frames(), expected);
  ASSERT_NE(tree.joint("needle_base_to_tip"), nullptr);
  EXPECT_FALSE(tree.joint("needle_base_to_tip")->tracked);
  EXPECT_TRUE(tree.joint("tracker_to_needle_marker")->tracked);
}

TEST(FrameTree, ChainsTrackedAndStaticJointsWithSlerpBetweenSamples) {
  FrameTree tree = load_station();
  const Transform a = pose(0.0, Eigen::Vector3d::UnitZ(), {0.1, 0.0, 0.0});
  const Transform b = pose(1.0, Eigen::Vector3d::UnitZ(), {0.3, 0.0, 0.0});
  ASSERT_TRUE(tree.add_pose("needle_marker", 1000, a).ok());
  ASSERT_TRUE(tree.add_pose("needle_marker", 3000, b).ok());
  // Half-way: rotation 0.5 rad about z, translation 0.2 m; the tip is 0.15 m along the marker's -z.
  auto tip = tree.lookup("tracker", "needle_tip", 2000);
  ASSERT_TRUE(tip.ok()) << tip.error().describe();
  EXPECT_NEAR(Eigen::AngleAxisd(tip.value().rotation()).angle(), 0.5, 1e-12);
  EXPECT_LT((tip.value().translation() - Eigen::Vector3d(0.2, 0.0, -0.15)).norm(), 1e-12);
  // The inverse lookup composes to the identity.
  auto back = tree.lookup("needle_tip", "tracker", 2000);
  ASSERT_TRUE(back.ok());
  EXPECT_TRUE((back.value() * tip.value()).matrix().isIdentity(1e-12));
}

TEST(FrameTree, TimesOutsideTheBufferedSpanAreErrors) {
  FrameTree tree = load_station();
  ASSERT_TRUE(tree.add_pose("probe_marker", 1000, Transform::Identity()).ok());
  ASSERT_TRUE(tree.add_pose("probe_marker", 2000, Transform::Identity()).ok());
  auto late = tree.lookup("tracker", "image_plane", 2001);
  ASSERT_FALSE(late.ok());
  EXPECT_NE(late.error().describe().find("outside the buffered span [1000, 2000]"), std::string::npos);
  EXPECT_FALSE(tree.lookup("tracker", "needle_tip", 1500).ok());         // needle never tracked
  auto static_chain = tree.lookup("needle_tip", "needle_marker", 1500);  // no tracked joint between them
  ASSERT_TRUE(static_chain.ok()) << static_chain.error().describe();
  EXPECT_NEAR(static_chain.value().translation().z(), 0.15, 1e-12);  // the marker seen from the tip, 0.15 m up its -z
  EXPECT_FALSE(tree.lookup("tracker", "nowhere", 1500).ok());
  EXPECT_FALSE(tree.add_pose("probe_marker", 2000, Transform::Identity()).ok());  // not increasing
  EXPECT_FALSE(tree.add_pose("needle_tip", 3000, Transform::Identity()).ok());    // fixed joint
}

TEST(FrameTree, CalibrationsAreWrittenBackAndReadAgain) {
  FrameTree tree = load_station();
  const Transform tip = pose(0.3, Eigen::Vector3d(1.0, 2.0, 3.0), {0.001, -0.002, 0.1534});
  ASSERT_TRUE(tree.set_calibration("needle_base_to_tip", tip, {"2026-11-21T12:00:00Z", 2.5e-5}).ok());
  EXPECT_FALSE(tree.set_calibration("tracker_to_needle_marker", tip, {"x", 0.0}).ok());
  const std::string path = temporary_path("frame_tree_calibrated.urdf");
  ASSERT_TRUE(tree.save(path).ok());
  auto reread = FrameTree::load(path);
  ASSERT_TRUE(reread.ok()) << reread.error().describe();
  const FrameJoint* joint = reread.value().joint("needle_base_to_tip");
  ASSERT_TRUE(joint->record.has_value());
  EXPECT_EQ(joint->record->date, "2026-11-21T12:00:00Z");
  EXPECT_DOUBLE_EQ(joint->record->residual_m, 2.5e-5);
  EXPECT_TRUE(joint->parent_from_child.isApprox(tip, 1e-12));
  EXPECT_FALSE(reread.value().joint("needle_marker_to_base")->record.has_value());
}

TEST(FrameTree, BadFilesNameTheFileAndTheElement) {
  const std::string bad_origin =
      "<robot name='r'>\n<link name='a'/><link name='b'/>\n"
      "<joint name='j' type='fixed'><parent link='a'/><child link='b'/>\n<origin xyz='0 zero 0'/></joint>\n</robot>";
  auto parsed = FrameTree::parse(bad_origin, "bad.urdf");
  ASSERT_FALSE(parsed.ok());
  EXPECT_EQ(parsed.error().file, "bad.urdf");
  EXPECT_EQ(parsed.error().line, 4);
  EXPECT_EQ(parsed.error().field, "joint j origin xyz");
  auto revolute = FrameTree::parse(
      "<robot name='r'><link name='a'/><link name='b'/><joint name='k' type='revolute'>"
      "<parent link='a'/><child link='b'/></joint></robot>",
      "r.urdf");
  ASSERT_FALSE(revolute.ok());
  EXPECT_EQ(revolute.error().field, "joint k");
  auto unknown_link = FrameTree::parse(
      "<robot name='r'><link name='a'/><joint name='k' type='fixed'><parent link='a'/><child "
      "link='zz'/></joint></robot>",
      "u.urdf");
  ASSERT_FALSE(unknown_link.ok());
  EXPECT_EQ(unknown_link.error().field, "joint k");
  EXPECT_NE(unknown_link.error().message.find("zz"), std::string::npos);
  EXPECT_FALSE(FrameTree::load(temporary_path("missing.urdf")).ok());
}

TEST(FrameTree, JointsThatDoNotFormOneTreeAreRejectedWithTheirName) {
  const auto parse = [](const std::string& body) {
    return FrameTree::parse("<robot name='r'><link name='a'/><link name='b'/><link name='c'/>" + body + "</robot>",
                            "t.urdf");
  };
  const std::string a_to_b = "<joint name='ab' type='fixed'><parent link='a'/><child link='b'/></joint>";
  const std::string b_to_c = "<joint name='bc' type='fixed'><parent link='b'/><child link='c'/></joint>";
  ASSERT_TRUE(parse(a_to_b + b_to_c).ok());

  auto cycle = parse(a_to_b + b_to_c + "<joint name='ca' type='fixed'><parent link='c'/><child link='a'/></joint>");
  ASSERT_FALSE(cycle.ok());
  EXPECT_NE(cycle.error().message.find("cycle"), std::string::npos) << cycle.error().message;

  auto self_loop = parse(a_to_b + "<joint name='cc' type='fixed'><parent link='c'/><child link='c'/></joint>");
  ASSERT_FALSE(self_loop.ok());
  EXPECT_EQ(self_loop.error().field, "link c");

  auto two_parents = parse(a_to_b + "<joint name='cb' type='fixed'><parent link='c'/><child link='b'/></joint>");
  ASSERT_FALSE(two_parents.ok());
  EXPECT_EQ(two_parents.error().field, "joint cb");

  auto two_roots = parse(a_to_b);
  ASSERT_FALSE(two_roots.ok());
  EXPECT_EQ(two_roots.error().field, "robot");

  auto duplicate_joint = parse(a_to_b + "<joint name='ab' type='fixed'><parent link='b'/><child link='c'/></joint>");
  ASSERT_FALSE(duplicate_joint.ok());
  EXPECT_EQ(duplicate_joint.error().field, "joint ab");
}

}  // namespace
}  // namespace nav::calibration
