// The PLUS sequence reader on the real recordings of ../shared/data/plus/ (compressed .mha,
// gzip .nrrd, a tracker-only buffer) and on small hand-written files, and its errors.
#include <gtest/gtest.h>

#include <string>

#include "nav/ultrasound/plus_sequence.hpp"
#include "nav/ultrasound/plus_sequence_writer.hpp"
#include "support/test_data.hpp"

namespace nav::ultrasound {
namespace {

std::string plus_path(const std::string& name) { return nav::testing::shared_data_path("plus/" + name); }

/// Two 3x2 frames, raw, with a ProbeToTracker transform each (the second one invalid).
std::string small_sequence() {
  return "ObjectType = Image\nNDims = 3\nCompressedData = False\nDimSize = 3 2 2\nElementSpacing = 0.2 0.3 1\n"
         "ElementType = MET_UCHAR\nUltrasoundImageOrientation = MF\n"
         "Seq_Frame0000_ProbeToTrackerTransform = 1 0 0 10 0 1 0 20 0 0 1 30 0 0 0 1\n"
         "Seq_Frame0000_ProbeToTrackerTransformStatus = OK\nSeq_Frame0000_Timestamp = 1.5\n"
         "Seq_Frame0000_ImageStatus = OK\n"
         "Seq_Frame0001_ProbeToTrackerTransform = 0 -1 0 1 1 0 0 2 0 0 1 3 0 0 0 1\n"
         "Seq_Frame0001_ProbeToTrackerTransformStatus = MISSING\nSeq_Frame0001_Timestamp = 1.6\n"
         "ElementDataFile = LOCAL\n"
         "abcdefghijkl";
}

TEST(PlusSequence, ReadsAHandWrittenRawFile) {
  const auto sequence = parse_plus_sequence(small_sequence(), "small.mha");
  ASSERT_TRUE(sequence.ok()) << sequence.error().describe();
  const PlusSequence& s = sequence.value();
  EXPECT_EQ(s.width_px, 3u);
  EXPECT_EQ(s.height_px, 2u);
  EXPECT_EQ(s.frame_count, 2u);
  EXPECT_EQ(s.frames_read, 2u);
  EXPECT_DOUBLE_EQ(s.spacing_mm[1], 0.3);
  EXPECT_EQ(s.image_orientation, "MF");
  EXPECT_DOUBLE_EQ(s.timestamps_s[1], 1.6);
  EXPECT_EQ(s.frame(1)[0], 'g');
  const TransformTrack* probe = s.find_transform("ProbeToTracker");
  ASSERT_NE(probe, nullptr);
  EXPECT_DOUBLE_EQ(probe->matrices_mm[0][7], 20.0);
  EXPECT_DOUBLE_EQ(probe->matrices_mm[1][1], -1.0);
  EXPECT_EQ(probe->valid[0], 1);
  EXPECT_EQ(probe->valid[1], 0);
  EXPECT_EQ(s.find_transform("StylusToTracker"), nullptr);
}

TEST(PlusSequence, CompressedRoundTripKeepsPixelsAndPoses) {
  const auto raw = parse_plus_sequence(small_sequence(), "small.mha").value();
  for (const bool compress : {false, true}) {
    const std::string text = format_plus_sequence(raw, compress);
    const auto again = parse_plus_sequence(text, "again.mha");
    ASSERT_TRUE(again.ok()) << again.error().describe();
    EXPECT_EQ(again.value().pixels, raw.pixels);
    EXPECT_EQ(again.value().timestamps_s, raw.timestamps_s);
    EXPECT_EQ(again.value().transforms[0].matrices_mm, raw.transforms[0].matrices_mm);
    EXPECT_EQ(again.value().transforms[0].valid, raw.transforms[0].valid);
  }
}

TEST(PlusSequence, ReadsOnlyTheFramesAsked) {
  const auto header_only = parse_plus_sequence(small_sequence(), "small.mha", {.max_frames = 0});
  ASSERT_TRUE(header_only.ok());
  EXPECT_EQ(header_only.value().frames_read, 0u);
  EXPECT_TRUE(header_only.value().pixels.empty());
  const auto one = parse_plus_sequence(small_sequence(), "small.mha", {.max_frames = 1});
  EXPECT_EQ(one.value().pixels.size(), 6u);
}

/// Replaces the first `from` in `text` by `to`.
std::string replaced(std::string text, const std::string& from, const std::string& to) {
  return text.replace(text.find(from), from.size(), to);
}

TEST(PlusSequence, BadInputNamesTheFileLineAndField) {
  const std::string good = small_sequence();
  const auto short_matrix = parse_plus_sequence(replaced(good, "0 0 1 30 0 0 0 1", "0 0 1 30 0 0 0"), "bad.mha");
  ASSERT_FALSE(short_matrix.ok());
  EXPECT_EQ(short_matrix.error().file, "bad.mha");
  EXPECT_EQ(short_matrix.error().line, 8);
  EXPECT_EQ(short_matrix.error().field, "Seq_Frame0000_ProbeToTrackerTransform");
  const auto no_time = parse_plus_sequence(replaced(good, "Seq_Frame0001_Timestamp = 1.6\n", ""), "bad.mha");
  ASSERT_FALSE(no_time.ok());
  EXPECT_EQ(no_time.error().field, "Seq_Frame1_Timestamp");
  const auto beyond =
      parse_plus_sequence(replaced(good, "Seq_Frame0001_Timestamp", "Seq_Frame0002_Timestamp"), "bad.mha");
  EXPECT_NE(beyond.error().message.find("beyond"), std::string::npos);
  const auto truncated = parse_plus_sequence(good.substr(0, good.size() - 1), "bad.mha");
  EXPECT_EQ(truncated.error().field, "pixel data");
  const auto corrupt =
      parse_plus_sequence(replaced(good, "CompressedData = False", "CompressedData = True"), "bad.mha");
  EXPECT_EQ(corrupt.error().field, "pixel data");
  const auto wide = parse_plus_sequence(replaced(good, "MET_UCHAR", "MET_SHORT"), "bad.mha");
  EXPECT_EQ(wide.error().field, "ElementType");
  EXPECT_EQ(wide.error().line, 6);
  EXPECT_FALSE(read_plus_sequence("/nonexistent/file.mha").ok());
}

TEST(PlusSequence, ReadsAHandWrittenRawNrrd) {
  const std::string nrrd =
      "NRRD0004\n# comment\ndimension: 3\nencoding: raw\nsizes: 2 2 2\ntype: uint8\n"
      "Seq_Frame0000_ProbeToTrackerTransform:=1 0 0 5 0 1 0 6 0 0 1 7 0 0 0 1\nSeq_Frame0000_Timestamp:=1.25\n"
      "Seq_Frame0001_Timestamp:=1.5\nSeq_Frame0001_Status:=INVALID\n\nabcdefgh";
  const auto sequence = parse_plus_sequence(nrrd, "small.nrrd");
  ASSERT_TRUE(sequence.ok()) << sequence.error().describe();
  EXPECT_EQ(sequence.value().frames_read, 2u);
  EXPECT_EQ(sequence.value().frame(1)[3], 'h');
  EXPECT_EQ(sequence.value().image_valid[1], 0);
  EXPECT_EQ(sequence.value().find_transform("ProbeToTracker")->valid[1], 0);  // not recorded for frame 1
  EXPECT_DOUBLE_EQ(sequence.value().find_transform("ProbeToTracker")->matrices_mm[0][11], 7.0);
  const auto bad = parse_plus_sequence(replaced(nrrd, "encoding: raw", "encoding: bzip2"), "bad.nrrd");
  ASSERT_FALSE(bad.ok());
  EXPECT_EQ(bad.error().line, 4);
  EXPECT_EQ(bad.error().field, "encoding");
  EXPECT_FALSE(parse_plus_sequence("NRRX0004\n", "bad.nrrd").ok());
}

TEST(PlusSequence, ReadsTheRealCompressedCalibrationRecording) {
  const std::string path = plus_path("fCal_Test_Calibration_3NWires_fCal2.0.igs.mha");
  NAV_REQUIRE_SHARED_DATA(path);
  const auto sequence = read_plus_sequence(path, {.max_frames = 2});
  ASSERT_TRUE(sequence.ok()) << sequence.error().describe();
  const PlusSequence& s = sequence.value();
  EXPECT_EQ(s.width_px, 820u);
  EXPECT_EQ(s.height_px, 616u);
  EXPECT_EQ(s.frame_count, 190u);
  EXPECT_EQ(s.frames_read, 2u);
  EXPECT_EQ(s.image_orientation, "MFA");
  EXPECT_DOUBLE_EQ(s.timestamps_s[0], 2572.905343);
  const TransformTrack* probe = s.find_transform("ProbeToTracker");
  ASSERT_NE(probe, nullptr);
  EXPECT_DOUBLE_EQ(probe->matrices_mm[0][3], 284.342);
  EXPECT_EQ(s.transforms.size(), 3u);
  std::size_t bright = 0;
  for (std::size_t i = 0; i < s.frame_pixels(); ++i) bright += s.frame(1)[i] > 128 ? 1 : 0;
  EXPECT_GT(bright, 100u);  // wires and phantom walls
}

TEST(PlusSequence, ReadsTheRealGzipNrrdRecording) {
  const std::string path = plus_path("NwirePhantomFreehand.igs.nrrd");
  NAV_REQUIRE_SHARED_DATA(path);
  const auto sequence = read_plus_sequence(path, {.max_frames = 1});
  ASSERT_TRUE(sequence.ok()) << sequence.error().describe();
  EXPECT_EQ(sequence.value().frame_count, 97u);
  EXPECT_EQ(sequence.value().frames_read, 1u);
  EXPECT_DOUBLE_EQ(sequence.value().find_transform("ProbeToTracker")->matrices_mm[0][3], -190.886);
  EXPECT_EQ(sequence.value().find_transform("StylusToTracker")->valid[0], 0);
  EXPECT_DOUBLE_EQ(sequence.value().timestamps_s[1], 345.706100);
}

TEST(PlusSequence, ReadsTheRealTrackerOnlyBuffer) {
  const std::string path = plus_path("WaterTankBottomTranslationTrackerBuffer-trimmed.igs.mha");
  NAV_REQUIRE_SHARED_DATA(path);
  const auto sequence = read_plus_sequence(path);
  ASSERT_TRUE(sequence.ok()) << sequence.error().describe();
  EXPECT_EQ(sequence.value().frame_count, 801u);
  EXPECT_EQ(sequence.value().frame_pixels(), 0u);
  EXPECT_DOUBLE_EQ(sequence.value().find_transform("ProbeToTracker")->matrices_mm[1][11], 6.69727);
  EXPECT_EQ(sequence.value().image_valid[0], 0);
}

}  // namespace
}  // namespace nav::ultrasound
