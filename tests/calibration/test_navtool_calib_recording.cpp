// navtool calib pivot on a DDS recording: a simulated pivoting needle (0.05 mm marker noise)
// and a second tool publish nav/tool_pose on real Fast DDS (loopback/shared memory only), the
// library's Recorder writes the recording, and the command finds the tip against truth.
#include <gtest/gtest.h>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <thread>

#include "calibration_truth.hpp"
#include "nav/calibration/frame_tree.hpp"
#include "nav/dds/dds_node.hpp"
#include "nav/dds/record_replay.hpp"
#include "support/run_command.hpp"
#include "support/test_data.hpp"

namespace nav::calibration {
namespace {

using namespace nav::calibration::testing;
using nav::testing::executable_path;
using nav::testing::run_command;
using nav::testing::temporary_path;

dds::ToolPose pose_sample(std::uint32_t tool_id, std::uint64_t sequence, TimeNs time_ns, const Transform& pose) {
  dds::ToolPose sample;
  sample.tool_id = tool_id;
  sample.sequence_number = sequence;
  sample.source_time_ns = time_ns;
  sample.position_m = {pose.translation().x(), pose.translation().y(), pose.translation().z()};
  const Eigen::Quaterniond q(pose.linear());
  sample.orientation_wxyz = {q.w(), q.x(), q.y(), q.z()};
  sample.quality = 1.0f;
  std::strcpy(sample.frame_to.data(), "tracker");
  std::strcpy(sample.frame_from.data(), "needle_marker");
  return sample;
}

/// Records `count` poses of a needle pivoting about (0, 0, -1) m with its tip at `tip_m` in
/// the marker frame (tool 3), interleaved with a static probe (tool 2); returns the records.
std::size_t record_pivoting_needle(const std::string& path, const Eigen::Vector3d& tip_m, int count) {
  dds::NetworkConfig network;
  network.domain_id = 171;
  network.participant_name = "nav_test_calib_recording";
  auto recorder =
      Result<std::unique_ptr<dds::Recorder>>(Error{.message = "not created"});  // outlives the node that fills it
  auto tracker = dds::DdsNode::create(network);
  auto recorder_node = dds::DdsNode::create(network);
  if (!tracker.ok() || !recorder_node.ok()) return 0;
  recorder = dds::Recorder::create(*recorder_node.value(), path);
  EXPECT_TRUE(recorder.ok()) << recorder.error().describe();
  if (!recorder.ok() || !tracker.value()->advertise<dds::ToolPose>().ok() ||
      !tracker.value()->wait_for_match(dds::Topic::tool_pose, 1, 10 * kNsPerSecond) ||
      !recorder_node.value()->wait_for_match(dds::Topic::tool_pose, 1, 10 * kNsPerSecond)) {
    return 0;
  }
  std::mt19937_64 rng(71);
  for (int i = 0; i < count; ++i) {
    const Eigen::Matrix3d rotation = random_rotation(rng, 0.5);
    const Eigen::Vector3d position = Eigen::Vector3d(0.0, 0.0, -1.0) - rotation * tip_m + gaussian_vector(rng, 0.05e-3);
    const TimeNs time_ns = (i + 1) * 20 * kNsPerMs;
    tracker.value()->write(pose_sample(3, static_cast<std::uint64_t>(i), time_ns, transform(rotation, position)));
    tracker.value()->write(pose_sample(2, static_cast<std::uint64_t>(i), time_ns + 1, Transform::Identity()));
    if (i % 4 == 3) {  // the recorder holds 16 samples a topic between pumps
      EXPECT_TRUE(tracker.value()->wait_for_acknowledgments(10 * kNsPerSecond));
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
      EXPECT_TRUE(recorder.value()->pump().ok());
    }
  }
  EXPECT_TRUE(tracker.value()->wait_for_acknowledgments(10 * kNsPerSecond));
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
  EXPECT_TRUE(recorder.value()->pump().ok());
  EXPECT_TRUE(recorder.value()->close().ok());
  auto reader = dds::RecordingReader::open(path);
  return reader.ok() ? reader.value()->record_count() : 0;
}

TEST(NavtoolCalibRecording, PivotFromADdsRecordingFindsTheTip) {
  const Eigen::Vector3d tip_m(0.002, 0.001, 0.17);
  const std::string recording = temporary_path("calib_pivot.navrec");
  const std::size_t records = record_pivoting_needle(recording, tip_m, 200);
  std::printf("recorded %zu of 400 poses\n", records);
  ASSERT_GE(records, 300u);  // both tools; a few may be dropped by the boundary queue

  const std::string out = temporary_path("calib_pivot_recording_station.urdf");
  const auto run = run_command(executable_path("navtool") + " calib pivot --recording " + recording +
                               " --tool 3 --urdf " + kStationUrdf + " --out " + out + " 2>&1");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  std::printf("%s", run.output.c_str());
  auto tree = FrameTree::load(out);
  ASSERT_TRUE(tree.ok()) << tree.error().describe();
  const FrameJoint* joint = tree.value().joint("needle_base_to_tip");
  ASSERT_NE(joint, nullptr);
  ASSERT_TRUE(joint->record.has_value());
  const double tip_error_m = (joint->parent_from_child.translation() - tip_m).norm();
  std::printf("tip error %.4f mm\n", tip_error_m * 1e3);
  EXPECT_LT(tip_error_m, 0.1e-3);
  EXPECT_NEAR(joint->record->residual_m, std::sqrt(3.0) * 0.05e-3, 0.02e-3);

  // The static probe alone has no rotation: a clear error, not a number.
  const auto probe =
      run_command(executable_path("navtool") + " calib pivot --recording " + recording + " --tool 2 2>&1");
  EXPECT_NE(probe.exit_code, 0);
  EXPECT_NE(probe.output.find("calib_pivot.navrec"), std::string::npos) << probe.output;
}

TEST(NavtoolCalibRecording, BadRecordingOptionsAreNamed) {
  const std::string not_recording = temporary_path("calib_not_a_recording.navrec");
  std::ofstream(not_recording) << "time_s,tool\n";
  const auto bad = run_command(executable_path("navtool") + " calib pivot --recording " + not_recording + " 2>&1");
  EXPECT_NE(bad.exit_code, 0);
  EXPECT_NE(bad.output.find("calib_not_a_recording.navrec"), std::string::npos) << bad.output;
  const auto both =
      run_command(executable_path("navtool") + " calib pivot --recording " + not_recording + " --poses x.csv 2>&1");
  EXPECT_NE(both.exit_code, 0);
  EXPECT_NE(both.output.find("exactly one"), std::string::npos) << both.output;
}

}  // namespace
}  // namespace nav::calibration
