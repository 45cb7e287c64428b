// navtool calib probe end to end: the real fCal 2.0 recordings in, the image-to-probe joint of
// the station URDF out (with its date and residual); a recording without the phantom and a
// recording without the named tracks are clear errors.
#include <gtest/gtest.h>

#include "nav/calibration/frame_tree.hpp"
#include "nav/ultrasound/plus_sequence_writer.hpp"
#include "support/run_command.hpp"
#include "support/test_data.hpp"

namespace nav::calibration {
namespace {

using nav::testing::executable_path;
using nav::testing::run_command;
using nav::testing::shared_data_path;
using nav::testing::temporary_path;

const std::string kStationUrdf = std::string(NAV_TEST_DATA_DIR) + "/../../calibration/urdf/station.urdf";

/// A small recording of `frames` blank 64 x 48 frames with identity probe and reference poses.
std::string blank_recording(std::size_t frames, bool with_reference) {
  ultrasound::PlusSequence sequence;
  sequence.width_px = 64;
  sequence.height_px = 48;
  sequence.frame_count = sequence.frames_read = frames;
  sequence.pixels.assign(sequence.frame_pixels() * frames, 0);
  sequence.image_valid.assign(frames, 1);
  for (std::size_t i = 0; i < frames; ++i) sequence.timestamps_s.push_back(0.1 * static_cast<double>(i));
  for (const char* name : {"ProbeToTracker", "ReferenceToTracker"}) {
    if (!with_reference && std::string(name) == "ReferenceToTracker") continue;
    ultrasound::TransformTrack track;
    track.name = name;
    track.matrices_mm.assign(frames, {1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1});
    track.valid.assign(frames, 1);
    sequence.transforms.push_back(track);
  }
  const std::string path = temporary_path(with_reference ? "calib_probe_blank.mha" : "calib_probe_no_reference.mha");
  EXPECT_TRUE(ultrasound::write_plus_sequence(path, sequence, true).ok());
  return path;
}

TEST(NavtoolCalibProbe, RealFcalRecordingWritesTheImageJoint) {
  const std::string xml = shared_data_path("plus/PlusDeviceSet_fCal_Sim_SpatialCalibration_2.0.xml");
  const std::string recording = shared_data_path("plus/fCal_Test_Calibration_3NWires_fCal2.0.igs.mha");
  const std::string validation = shared_data_path("plus/fCal_Test_Validation_3NWires_fCal2.0.igs.mha");
  NAV_REQUIRE_SHARED_DATA(recording);
  NAV_REQUIRE_SHARED_DATA(validation);
  const std::string out = temporary_path("calib_probe_station.urdf");
  const auto run =
      run_command(executable_path("navtool") + " calib probe --recording " + recording + " --phantom " + xml +
                  " --validation " + validation + " --urdf " + kStationUrdf + " --out " + out + " 2>&1");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("validation: "), std::string::npos) << run.output;
  auto tree = FrameTree::load(out);
  ASSERT_TRUE(tree.ok()) << tree.error().describe();
  const FrameJoint* joint = tree.value().joint("probe_marker_to_image");
  ASSERT_TRUE(joint->record.has_value());
  EXPECT_GT(joint->record->residual_m, 0.1e-3);
  EXPECT_LT(joint->record->residual_m, 1.0e-3);
  // The image origin lies a few centimetres from the probe marker, not at it.
  EXPECT_GT(joint->parent_from_child.translation().norm(), 0.01);
  EXPECT_LT(joint->parent_from_child.translation().norm(), 0.3);
}

TEST(NavtoolCalibProbe, PhantomNotFoundAndMissingTrackAreErrors) {
  const std::string xml = shared_data_path("plus/PlusDeviceSet_fCal_Sim_SpatialCalibration_2.0.xml");
  NAV_REQUIRE_SHARED_DATA(xml);
  const std::string blank = blank_recording(12, true);
  const auto not_found =
      run_command(executable_path("navtool") + " calib probe --recording " + blank + " --phantom " + xml + " 2>&1");
  EXPECT_EQ(not_found.exit_code, 2);
  EXPECT_NE(not_found.output.find("found in 0 of 12 frames"), std::string::npos) << not_found.output;
  const std::string no_reference = blank_recording(12, false);
  const auto missing = run_command(executable_path("navtool") + " calib probe --recording " + no_reference +
                                   " --phantom " + xml + " 2>&1");
  EXPECT_EQ(missing.exit_code, 2);
  EXPECT_NE(missing.output.find("ReferenceToTracker: no such transform"), std::string::npos) << missing.output;
}

}  // namespace
}  // namespace nav::calibration
