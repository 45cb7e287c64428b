// navtool record and navtool replay as command lines: a recording replayed by one process
// is recorded by another, which stops on SIGTERM with an intact, indexed file holding the
// same samples byte for byte; a truncated recording replays its intact part and says where
// it is damaged; and replay's wait for readers is an option, not a constant.
#include <gtest/gtest.h>

#include <csignal>
#include <filesystem>
#include <map>
#include <utility>

#include "child_process.hpp"
#include "dds_test_samples.hpp"
#include "nav/dds/recording_file.hpp"
#include "nav/dds/sample_codec.hpp"
#include "support/run_command.hpp"

namespace nav::dds {
namespace {

using namespace testing;
using nav::testing::ChildProcess;

constexpr auto kProcessTimeout = std::chrono::seconds(60);

/// Every record of a recording, by (topic, source time), as its CDR payload.
using RecordedPayloads = std::map<std::pair<Topic, TimeNs>, std::vector<std::uint8_t>>;

template <typename Sample>
void append(RecordingWriter& writer, const Sample& sample, TimeNs receive_time_ns, RecordedPayloads& written) {
  std::vector<std::uint8_t> bytes;
  ASSERT_TRUE(encode_sample(sample, bytes));
  ASSERT_TRUE(writer.append(topic_of<Sample>(), sample.source_time_ns, receive_time_ns, bytes).ok());
  written[{topic_of<Sample>(), sample.source_time_ns}] = bytes;
}

/// A recording of 8 rounds, 20 ms apart, of a needle state, a prediction and a 320 x 240
/// frame (24 records); returns the payloads written.
RecordedPayloads write_input_recording(const std::string& path) {
  RecordedPayloads written;
  auto writer = RecordingWriter::create(path);
  EXPECT_TRUE(writer.ok());
  for (TimeNs round = 1; round <= 8; ++round) {
    const TimeNs time_ns = round * 20 * kNsPerMs;
    append(*writer.value(), make_needle(16, time_ns), time_ns + 1000, written);
    append(*writer.value(), make_prediction(time_ns), time_ns + 2000, written);
    append(*writer.value(), *make_frame(320, 240, time_ns), time_ns + 3000, written);
  }
  EXPECT_TRUE(writer.value()->close().ok());
  return written;
}

RecordedPayloads read_recording(RecordingReader& reader) {
  RecordedPayloads payloads;
  for (std::size_t i = 0; i < reader.record_count(); ++i) {
    auto record = reader.read(i);
    EXPECT_TRUE(record.ok()) << record.error().describe();
    if (record.ok()) payloads[{record.value().topic, record.value().source_time_ns}] = record.value().payload;
  }
  return payloads;
}

TEST(NavtoolRecordReplay, ReplayedRecordingIsRecordedUnchangedAndSigtermClosesIt) {
  const std::string input = nav::testing::temporary_path("navtool_cli_input.navrec");
  const std::string output = nav::testing::temporary_path("navtool_cli_output.navrec");
  std::filesystem::remove(output);
  const RecordedPayloads written = write_input_recording(input);
  ASSERT_EQ(written.size(), 24u);

  ChildProcess recorder(
      {nav::testing::executable_path("navtool"), "record", "--out", output, "--duration-s", "120", "--domain", "160"},
      nav::testing::temporary_path("navtool_cli_record.log"));
  ASSERT_TRUE(recorder.started());
  ChildProcess player(
      {nav::testing::executable_path("navtool"), "replay", input, "--wait-for-readers-s", "30", "--domain", "160"},
      nav::testing::temporary_path("navtool_cli_replay.log"));
  EXPECT_EQ(player.wait(kProcessTimeout), 0) << player.log();
  EXPECT_NE(player.log().find("replayed 24 samples, skipped 0"), std::string::npos) << player.log();

  std::this_thread::sleep_for(std::chrono::milliseconds(300));  // the last samples reach the recorder
  recorder.signal(SIGTERM);
  ASSERT_EQ(recorder.wait(kProcessTimeout), 0) << recorder.log();
  EXPECT_NE(recorder.log().find("recorded "), std::string::npos) << recorder.log();

  auto reader = RecordingReader::open(output);
  ASSERT_TRUE(reader.ok()) << reader.error().describe();
  EXPECT_TRUE(reader.value()->indexed()) << "SIGTERM must close the recording with its index";
  EXPECT_FALSE(reader.value()->damage().has_value());
  const RecordedPayloads recorded = read_recording(*reader.value());
  // Needle and predictions are reliable keep-last 1: the latest sample is guaranteed, an
  // intermediate one may be replaced before it is acknowledged on a loaded machine. Frames are
  // best-effort.
  std::map<Topic, std::size_t> per_topic;
  for (const auto& [key, payload] : recorded) {
    ++per_topic[key.first];
    const auto original = written.find(key);
    ASSERT_NE(original, written.end()) << "recorded a sample nobody sent, source time " << key.second;
    EXPECT_EQ(payload, original->second) << topic_name(key.first) << " at " << key.second;
  }
  constexpr TimeNs kLastRoundNs = 8 * 20 * kNsPerMs;
  EXPECT_EQ(recorded.count({Topic::needle_state, kLastRoundNs}), 1u) << "the latest needle state must arrive";
  EXPECT_EQ(recorded.count({Topic::target_prediction, kLastRoundNs}), 1u) << "the latest prediction must arrive";
  EXPECT_GE(per_topic[Topic::needle_state], 6u);
  EXPECT_GE(per_topic[Topic::target_prediction], 6u);
  EXPECT_GE(per_topic[Topic::ultrasound_frame], 6u);
}

TEST(NavtoolRecordReplay, TruncatedRecordingPlaysItsIntactPartAndNamesTheOffset) {
  const std::string input = nav::testing::temporary_path("navtool_cli_truncated.navrec");
  write_input_recording(input);
  std::uint64_t fourth_record_offset = 0;
  {
    auto reader = RecordingReader::open(input);
    ASSERT_TRUE(reader.ok());
    fourth_record_offset = reader.value()->read(3).value().offset;
  }
  std::filesystem::resize_file(input, fourth_record_offset + 10);
  // Nobody listens on this domain: a short wait for readers keeps the test quick.
  ChildProcess player({nav::testing::executable_path("navtool"), "replay", input, "--as-fast-as-possible",
                       "--wait-for-readers-s", "0.1", "--domain", "161"},
                      nav::testing::temporary_path("navtool_cli_truncated.log"));
  EXPECT_EQ(player.wait(kProcessTimeout), 1) << player.log();
  const std::string log = player.log();
  EXPECT_NE(log.find("byte offset " + std::to_string(fourth_record_offset)), std::string::npos) << log;
  EXPECT_NE(log.find("replayed 3 samples"), std::string::npos) << log;
}

TEST(NavtoolRecordReplay, MalformedCommandLinesAreRefused) {
  for (const std::vector<std::string>& args :
       {std::vector<std::string>{nav::testing::executable_path("navtool"), "replay", "x.navrec", "--wait-for-readers-s",
                                 "-1"},
        std::vector<std::string>{nav::testing::executable_path("navtool"), "replay", "x.navrec",
                                 "--wait-for-readers-s"},
        std::vector<std::string>{nav::testing::executable_path("navtool"), "record", "--duration-s", "1"}}) {
    ChildProcess tool(args, nav::testing::temporary_path("navtool_cli_usage.log"));
    EXPECT_EQ(tool.wait(kProcessTimeout), 2) << args[1] << " " << args.back();
    EXPECT_NE(tool.log().find("usage: navtool"), std::string::npos) << tool.log();
  }
}

}  // namespace
}  // namespace nav::dds
