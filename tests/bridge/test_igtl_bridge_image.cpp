// The ultrasound frame reaches a display as SlicerIGT's Image_Reference: the devices publish a
// frame, the probe's tracked poses around its capture time and the reference tool's pose; the
// bridge places the image in the model frame through the scene's registration and the URDF's
// probe calibration. Read back as Slicer reads an IMAGE (the matrix holds the image's centre;
// Slicer takes it back to the first pixel), the first pixel and the image axes are those
// computed here from the URDF's joints and the poses sent, and every pixel is the frame's. A
// frame without a probe pose around its time is not sent, and is counted.
#include <gtest/gtest.h>
#include <igtlImageMessage.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstring>
#include <memory>
#include <thread>

#include "bridge_test_support.hpp"
#include "nav/bridge/igtl_bridge.hpp"
#include "nav/calibration/frame_tree.hpp"
#include "nav/dds/dds_node.hpp"
#include "nav/igtl/wall_clock.hpp"
#include "nav/station/station_dds.hpp"

namespace nav::bridge {
namespace {

using nav::testing::SlicerClient;
using nav::testing::unpack_into;
using nav::testing::wait_until;

constexpr std::uint32_t kDomain = 225;
constexpr std::uint32_t kProbeTool = 2;      // the demo scene's
constexpr std::uint32_t kReferenceTool = 4;  // declared below
constexpr TimeNs kTimeoutNs = 10 * kNsPerSecond;

/// The demo scene with a tracked reference tool, and displays on a port of the system's choice.
station::Scene scene_with_reference() {
  const std::string text = nav::testing::edited(nav::testing::edited(nav::testing::movable_demo_text(), "domain_id: 0",
                                                                     "domain_id: " + std::to_string(kDomain)),
                                                "    seed: 1\n", "    seed: 1\n    tools: {reference: 4}\n") +
                           "\nopenigtlink:\n  displays: 127.0.0.1:0\n";
  auto scene = station::parse_scene(text, nav::testing::example_scene_path("bridge_image_test.yaml"));
  EXPECT_TRUE(scene.ok()) << (scene.ok() ? "" : scene.error().describe());
  return scene.ok() ? std::move(scene).value() : station::Scene{};
}

dds::ToolPose pose_of(std::uint32_t tool, TimeNs time_ns, const Eigen::Isometry3d& tracker_from_tool) {
  dds::ToolPose pose;
  pose.tool_id = tool;
  pose.source_time_ns = time_ns;
  const Eigen::Quaterniond q(tracker_from_tool.rotation());
  pose.orientation_wxyz = {q.w(), q.x(), q.y(), q.z()};
  for (int i = 0; i < 3; ++i) pose.position_m[static_cast<std::size_t>(i)] = tracker_from_tool.translation()[i];
  pose.quality = 1.0f;
  return pose;
}

Eigen::Isometry3d isometry(double angle_rad, const Eigen::Vector3d& axis, const Eigen::Vector3d& translation_m) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = Eigen::AngleAxisd(angle_rad, axis.normalized()).toRotationMatrix();
  t.translation() = translation_m;
  return t;
}

TEST(IgtlBridgeImage, TheUltrasoundFrameArrivesWhereTheTrackedProbeHoldsIt) {
  const station::Scene scene = scene_with_reference();
  auto bridge = IgtlBridge::open(scene);
  ASSERT_TRUE(bridge.ok()) << bridge.error().describe();
  auto made = station::make_station_node(kDomain, "test_devices", station::topic_names(scene.topics), scene.network,
                                         station::Role::devices);
  ASSERT_TRUE(made.ok()) << made.error().describe();
  dds::DdsNode& devices = *made.value();
  ASSERT_TRUE(devices.advertise<dds::ToolPose>().ok());
  ASSERT_TRUE(devices.advertise<dds::UltrasoundFrame>().ok());
  const nav::testing::RunningBridge running(*bridge.value());
  for (const dds::Topic topic : {dds::Topic::tool_pose, dds::Topic::ultrasound_frame})
    ASSERT_TRUE(devices.wait_for_match(topic, 1, kTimeoutNs));  // the bridge's display side

  SlicerClient slicer;
  ASSERT_EQ(slicer.socket->ConnectToServer("127.0.0.1", bridge.value()->displays_port()), 0);
  slicer.socket->SetReceiveTimeout(100);

  auto frame = std::make_unique<dds::UltrasoundFrame>();
  frame->probe_tool_id = kProbeTool;
  frame->width_px = 64;
  frame->height_px = 48;
  frame->pixel_spacing_m = {0.2e-3, 0.25e-3};
  frame->depth_m = 48 * 0.25e-3;
  for (std::size_t i = 0; i < frame->pixel_count(); ++i) frame->pixels[i] = static_cast<std::uint8_t>(i * 13 + 5);
  MonotonicClock clock;

  // No probe pose yet: the frame is not sent, and is counted.
  ASSERT_TRUE(wait_until([&] {
    frame->source_time_ns = clock.now_ns();
    devices.write(*frame);
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    return bridge.value()->totals().images_unplaced >= 1;
  }));

  // The probe at p1 10 ms before the capture and at p2 10 ms after; the reference elsewhere.
  const Eigen::Isometry3d tracker_from_reference = isometry(0.35, {0, 0, 1}, {0.10, -0.05, 0.20});
  const Eigen::Isometry3d probe_at_p1 = isometry(0.5, {1, 1, 0}, {0.02, 0.03, 0.15});
  Eigen::Isometry3d probe_at_p2 = probe_at_p1;
  probe_at_p2.translation() += Eigen::Vector3d(0.004, -0.002, 0.006);
  ASSERT_TRUE(wait_until([&] {
    const TimeNs capture_ns = clock.now_ns() - 20 * kNsPerMs;
    devices.write(pose_of(kReferenceTool, capture_ns, tracker_from_reference));
    devices.write(pose_of(kProbeTool, capture_ns - 10 * kNsPerMs, probe_at_p1));
    devices.write(pose_of(kProbeTool, capture_ns + 10 * kNsPerMs, probe_at_p2));
    std::this_thread::sleep_for(std::chrono::milliseconds(40));  // the poses first, as a tracker's come
    frame->source_time_ns = capture_ns;
    devices.write(*frame);
    while (slicer.receive()) {
    }
    return slicer.newest.count("Image_Reference") == 1;
  })) << "no Image_Reference; "
      << bridge.value()->totals().images_unplaced << " frames unplaced";

  // The placement expected, from the URDF's joints and the poses sent (the probe midway).
  auto frames = calibration::FrameTree::load(scene.frames.urdf_path);
  ASSERT_TRUE(frames.ok()) << frames.error().describe();
  auto reference_from_model = frames.value().lookup("reference_marker", "liver_model", 0);
  auto probe_from_image = frames.value().lookup("probe_marker", "image_plane", 0);
  ASSERT_TRUE(reference_from_model.ok() && probe_from_image.ok());
  Eigen::Isometry3d tracker_from_probe = probe_at_p1;
  tracker_from_probe.translation() = 0.5 * (probe_at_p1.translation() + probe_at_p2.translation());
  const Eigen::Isometry3d model_from_image =
      (tracker_from_reference * reference_from_model.value()).inverse() * tracker_from_probe * probe_from_image.value();

  ::igtl::ImageMessage::Pointer image = ::igtl::ImageMessage::New();
  unpack_into(slicer.newest["Image_Reference"], image);
  int size[3];
  float spacing_mm[3];
  ::igtl::Matrix4x4 m;
  image->GetDimensions(size);
  image->GetSpacing(spacing_mm);
  image->GetMatrix(m);
  ASSERT_EQ(size[0], 64);
  ASSERT_EQ(size[1], 48);
  EXPECT_FLOAT_EQ(spacing_mm[0], 0.2f);
  EXPECT_FLOAT_EQ(spacing_mm[1], 0.25f);
  EXPECT_EQ(std::memcmp(image->GetScalarPointer(), frame->pixels.data(), frame->pixel_count()), 0);
  // Slicer's reading: unit axes from the matrix's columns, the first pixel half the image back from its centre.
  Eigen::Matrix3d axes;
  Eigen::Vector3d centre_mm;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) axes(r, c) = m[r][c];
    centre_mm[r] = m[r][3];
  }
  for (int c = 0; c < 3; ++c) axes.col(c).normalize();
  const Eigen::Vector3d first_pixel_mm =
      centre_mm - axes * Eigen::Vector3d(0.5 * spacing_mm[0] * (size[0] - 1), 0.5 * spacing_mm[1] * (size[1] - 1), 0.0);
  EXPECT_LT((first_pixel_mm - 1e3 * model_from_image.translation()).norm(), 0.01)
      << "first pixel at " << first_pixel_mm.transpose() << " mm, expected "
      << 1e3 * model_from_image.translation().transpose();
  EXPECT_LT((axes - model_from_image.rotation()).cwiseAbs().maxCoeff(), 1e-5);
  unsigned seconds = 0, fraction = 0;
  image->GetTimeStamp(&seconds, &fraction);
  EXPECT_NEAR(static_cast<double>(seconds) - 1e-9 * static_cast<double>(igtl::wall_now_ns()), 0.0, 5.0)
      << "stamped in wall-clock time";
}

}  // namespace
}  // namespace nav::bridge
