// Recordings: every topic round-trips through the file with its times; a truncated file
// or a corrupt record is reported with its byte offset and the intact records still play;
// and samples recorded from DDS replay onto DDS unchanged.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "dds_test_samples.hpp"
#include "nav/dds/pose_inbox.hpp"
#include "nav/dds/record_replay.hpp"
#include "nav/dds/sample_codec.hpp"
#include "support/test_data.hpp"

namespace nav::dds {
namespace {

using namespace testing;

/// Writes one record of `sample` with receive time source + 1000.
template <typename Sample>
void append(RecordingWriter& writer, const Sample& sample) {
  std::vector<std::uint8_t> bytes;
  ASSERT_TRUE(encode_sample(sample, bytes));
  ASSERT_TRUE(writer.append(topic_of<Sample>(), sample.source_time_ns, sample.source_time_ns + 1000, bytes).ok());
}

/// A closed recording of five poses (times 10..50) at `path`; returns the record offsets.
std::vector<std::uint64_t> write_five_poses(const std::string& path) {
  auto writer = RecordingWriter::create(path);
  EXPECT_TRUE(writer.ok());
  for (int i = 1; i <= 5; ++i) append(*writer.value(), make_pose(1, 10 * i));
  EXPECT_TRUE(writer.value()->close().ok());
  auto reader = RecordingReader::open(path);
  std::vector<std::uint64_t> offsets;
  for (std::size_t i = 0; i < reader.value()->record_count(); ++i)
    offsets.push_back(reader.value()->read(i).value().offset);
  return offsets;
}

TEST(DdsRecording, EveryTopicRoundTripsWithItsTimes) {
  const std::string path = nav::testing::temporary_path("nav_all_topics.navrec");
  {
    auto writer = RecordingWriter::create(path);
    ASSERT_TRUE(writer.ok()) << writer.error().describe();
    append(*writer.value(), make_pose(1, 100));
    append(*writer.value(), *make_frame(320, 240, 200));
    append(*writer.value(), make_needle(12, 300));
    append(*writer.value(), make_prediction(400));
    append(*writer.value(), *make_surface(500, 500));
    append(*writer.value(), make_health(600));
    append(*writer.value(), make_truth(700));
    append(*writer.value(), make_needle_force(800));
    ASSERT_TRUE(writer.value()->close().ok());
  }
  auto reader = RecordingReader::open(path);
  ASSERT_TRUE(reader.ok()) << reader.error().describe();
  EXPECT_TRUE(reader.value()->indexed());
  EXPECT_FALSE(reader.value()->damage().has_value());
  ASSERT_EQ(reader.value()->record_count(), kTopicCount);
  const Topic topics[] = {Topic::tool_pose,         Topic::ultrasound_frame, Topic::needle_state,
                          Topic::target_prediction, Topic::deformed_surface, Topic::station_health,
                          Topic::ground_truth,      Topic::needle_force};
  static_assert(std::size(topics) == kTopicCount, "every topic is recorded");
  for (std::size_t i = 0; i < kTopicCount; ++i) {
    auto record = reader.value()->read(i);
    ASSERT_TRUE(record.ok()) << record.error().describe();
    EXPECT_EQ(record.value().topic, topics[i]);
    EXPECT_EQ(record.value().source_time_ns, static_cast<TimeNs>(100 * (i + 1)));
    EXPECT_EQ(record.value().receive_time_ns, static_cast<TimeNs>(100 * (i + 1) + 1000));
  }
  auto frame = std::make_unique<UltrasoundFrame>();
  const auto frame_record = reader.value()->read(1).value();
  ASSERT_EQ(decode_sample(frame_record.payload.data(), frame_record.payload.size(), *frame), SampleFault::none);
  EXPECT_EQ(std::memcmp(frame->pixels.data(), make_frame(320, 240, 0)->pixels.data(), 320 * 240), 0);
}

TEST(DdsRecording, TruncatedRecordingReportsTheOffsetAndItsIntactPartPlays) {
  const std::string path = nav::testing::temporary_path("nav_truncated.navrec");
  const std::vector<std::uint64_t> offsets = write_five_poses(path);
  ASSERT_EQ(offsets.size(), 5u);
  std::filesystem::resize_file(path, offsets[3] + 40);  // inside the fourth record's payload
  auto reader = RecordingReader::open(path);
  ASSERT_TRUE(reader.ok()) << reader.error().describe();
  EXPECT_FALSE(reader.value()->indexed());
  ASSERT_TRUE(reader.value()->damage().has_value());
  const std::string damage = reader.value()->damage()->describe();
  EXPECT_NE(damage.find("truncated record payload at byte offset " + std::to_string(offsets[3])), std::string::npos)
      << damage;
  ASSERT_EQ(reader.value()->record_count(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    auto record = reader.value()->read(i);
    ASSERT_TRUE(record.ok());
    ToolPose pose;
    EXPECT_EQ(decode_sample(record.value().payload.data(), record.value().payload.size(), pose), SampleFault::none);
    EXPECT_EQ(pose.source_time_ns, static_cast<TimeNs>(10 * (i + 1)));
  }
}

TEST(DdsRecording, CorruptRecordIsReportedWithItsOffsetAndTheOthersStillPlay) {
  const std::string path = nav::testing::temporary_path("nav_corrupt.navrec");
  const std::vector<std::uint64_t> offsets = write_five_poses(path);
  {
    std::fstream file(path, std::ios::in | std::ios::out | std::ios::binary);
    file.seekp(static_cast<std::streamoff>(offsets[1] + 32 + 20));
    file.put('\x5a');
  }
  auto reader = RecordingReader::open(path);
  ASSERT_TRUE(reader.ok());
  EXPECT_TRUE(reader.value()->indexed());
  ASSERT_EQ(reader.value()->record_count(), 5u);
  const auto damaged = reader.value()->read(1);
  ASSERT_FALSE(damaged.ok());
  EXPECT_NE(damaged.error().describe().find("checksum mismatch at byte offset " + std::to_string(offsets[1])),
            std::string::npos)
      << damaged.error().describe();
  for (const std::size_t i : {0u, 2u, 3u, 4u}) EXPECT_TRUE(reader.value()->read(i).ok()) << i;
}

TEST(DdsRecording, NotARecordingIsAnError) {
  const std::string path = nav::testing::temporary_path("nav_not_a_recording.navrec");
  std::ofstream(path) << "hello";
  const auto reader = RecordingReader::open(path);
  ASSERT_FALSE(reader.ok());
  EXPECT_NE(reader.error().describe().find("not a navigation recording"), std::string::npos);
  EXPECT_FALSE(RecordingReader::open(nav::testing::temporary_path("nav_missing.navrec")).ok());
}

TEST(DdsRecording, RecordedPosesReplayOntoDdsUnchanged) {
  const std::string path = nav::testing::temporary_path("nav_dds_round_trip.navrec");
  std::vector<TimeNs> sent_ns;
  {
    auto recorder =
        Result<std::unique_ptr<Recorder>>(Error{.message = "not created"});  // outlives the node that fills it
    auto tracker = DdsNode::create(local_network(111));
    auto recorder_node = DdsNode::create(local_network(111));
    ASSERT_TRUE(tracker.ok() && recorder_node.ok());
    recorder = Recorder::create(*recorder_node.value(), path);
    ASSERT_TRUE(recorder.ok()) << recorder.error().describe();
    ASSERT_TRUE(tracker.value()->advertise<ToolPose>().ok());
    ASSERT_TRUE(tracker.value()->wait_for_match(Topic::tool_pose, 1, 10 * kNsPerSecond));
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    for (int i = 1; i <= 20; ++i) {
      sent_ns.push_back(1000 * i);
      tracker.value()->write(make_pose(1, 1000 * i));
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
      ASSERT_TRUE(recorder.value()->pump().ok());
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
    ASSERT_TRUE(recorder.value()->pump().ok());
    ASSERT_TRUE(recorder.value()->close().ok());
  }
  auto recording = RecordingReader::open(path);
  ASSERT_TRUE(recording.ok());
  const std::size_t recorded = recording.value()->record_count();
  std::printf("recorded %zu of 20 poses\n", recorded);
  EXPECT_GE(recorded, 10u);

  auto player = DdsNode::create(local_network(112));
  auto display = DdsNode::create(local_network(112));
  ASSERT_TRUE(player.ok() && display.ok());
  auto poses = std::make_unique<RingSink<ToolPose, 64>>();
  ASSERT_TRUE(display.value()->subscribe(*poses).ok());
  const ReplayReport report = replay(*recording.value(), *player.value(), ReplayPace::recorded, 10 * kNsPerSecond);
  EXPECT_EQ(report.published, recorded);
  EXPECT_EQ(report.skipped, 0u);
  ASSERT_TRUE(wait_until([&] { return poses->size() >= recorded * 8 / 10; }));
  ToolPose pose;
  while (poses->try_pop(pose)) {
    EXPECT_NE(std::find(sent_ns.begin(), sent_ns.end(), pose.source_time_ns), sent_ns.end());
    EXPECT_EQ(pose.orientation_wxyz, make_pose(1, 0).orientation_wxyz);
  }
}

}  // namespace
}  // namespace nav::dds
