// Samples no Fast DDS writer of the station's types would send, sent anyway: payloads under
// another CDR encapsulation (XCDR2 0x0007, parameter lists), a first byte of 0x01, cut short.
// The generated decoder throws on some of them on Fast DDS's receive thread, which once ended
// navstation and navtool record (std::terminate). Each is a counted `malformed` refusal here:
// in the decoder alone, in a reader of this process fed over UDP by a participant of "another
// vendor", and in a running navtool record and navstation, which finish with their summaries.
// A needle pose at 1e300 m is refused as implausible. A sample stamped far ahead of its arrival is refused by a reader
// that holds its stream to an arrival window, and never becomes the stream's time reference (which once made every
// later sample "backwards"). A participant killed with SIGKILL leaves its shared-memory segment behind; the next one to
// start removes it.
#include <gtest/gtest.h>
#include <sys/file.h>

#include <chrono>
#include <csignal>
#include <filesystem>
#include <fstream>
#include <limits>
#include <set>
#include <string>
#include <thread>
#include <utility>
#include <vector>

#include "child_process.hpp"
#include "dds_test_samples.hpp"
#include "nav/core/clock.hpp"
#include "nav/dds/checked_type.hpp"
#include "nav/dds/dds_node.hpp"
#include "nav/dds/pose_inbox.hpp"
#include "nav/dds/recording_file.hpp"
#include "nav/dds/sample_codec.hpp"
#include "nav/dds/shared_memory_cleanup.hpp"
#include "raw_payload_writer.hpp"
#include "support/run_command.hpp"

namespace nav::dds {
namespace {

using namespace testing;
using nav::testing::ChildProcess;

using Payload = std::vector<std::uint8_t>;

/// Payloads made from the valid encoding `valid`, none of which a station may take.
std::vector<std::pair<std::string, Payload>> crafted_payloads(const Payload& valid) {
  const auto edited = [&valid](std::uint8_t first, std::uint8_t second) {
    Payload bytes = valid;
    bytes[0] = first;
    bytes[1] = second;
    return bytes;
  };
  return {{"XCDR2 encapsulation 0x0007", edited(0x00, 0x07)},
          {"first byte 0x01", edited(0x01, 0x00)},
          {"parameter-list encapsulation 0x0003", edited(0x00, 0x03)},
          {"encapsulation 0x0101", edited(0x01, 0x01)},
          {"encapsulation header alone", Payload(valid.begin(), valid.begin() + 4)},
          {"cut in half", Payload(valid.begin(), valid.begin() + static_cast<std::ptrdiff_t>(valid.size() / 2))}};
}

template <typename Sample>
Payload encoded(const Sample& sample) {
  Payload bytes;
  EXPECT_TRUE(encode_sample(sample, bytes));
  return bytes;
}

/// Every crafted payload of `valid` through Sample's checked type: refused as malformed and
/// counted, where the generated type itself throws on at least one of them.
template <typename Sample>
void expect_refused_by_the_checked_type(const Payload& valid) {
  BoundaryCounters counters;
  CheckedPubSubType<Sample> checked(counters);
  typename WireTraits<Sample>::PubSubType generated;
  auto wire = std::make_unique<typename WireTraits<Sample>::Wire>();
  std::size_t generated_throws = 0;
  const auto crafted = crafted_payloads(valid);
  for (const auto& [what, bytes] : crafted) {
    eprosima::fastrtps::rtps::SerializedPayload_t payload(static_cast<std::uint32_t>(bytes.size()));
    std::memcpy(payload.data, bytes.data(), bytes.size());
    payload.length = static_cast<std::uint32_t>(bytes.size());
    EXPECT_FALSE(checked.deserialize(&payload, wire.get())) << what;
    try {
      generated.deserialize(&payload, wire.get());
    } catch (...) {
      ++generated_throws;
    }
    auto sample = std::make_unique<Sample>();
    EXPECT_EQ(decode_sample(bytes.data(), bytes.size(), *sample), SampleFault::malformed) << what;
  }
  EXPECT_EQ(counters.snapshot().malformed, crafted.size());
  EXPECT_GE(generated_throws, 2u) << "the generated decoder no longer throws: the hazard this test guards is gone";
  // The valid payload still decodes, in both encapsulations of plain CDR.
  eprosima::fastrtps::rtps::SerializedPayload_t payload(static_cast<std::uint32_t>(valid.size()));
  std::memcpy(payload.data, valid.data(), valid.size());
  payload.length = static_cast<std::uint32_t>(valid.size());
  EXPECT_TRUE(checked.deserialize(&payload, wire.get()));
  EXPECT_EQ(counters.snapshot().malformed, crafted.size());
}

TEST(DdsHostileSamples, EveryTypeRefusesForeignEncapsulationsAsCountedMalformedSamples) {
  expect_refused_by_the_checked_type<ToolPose>(encoded(make_pose(1, 1000)));
  expect_refused_by_the_checked_type<UltrasoundFrame>(encoded(*make_frame(32, 24, 2000)));
  expect_refused_by_the_checked_type<NeedleState>(encoded(make_needle(8, 3000)));
  expect_refused_by_the_checked_type<TargetPrediction>(encoded(make_prediction(4000)));
  expect_refused_by_the_checked_type<DeformedSurface>(encoded(*make_surface(16, 5000)));
  expect_refused_by_the_checked_type<StationHealth>(encoded(make_health(6000)));
}

TEST(DdsHostileSamples, PlainCdrIsTheOnlyEncapsulationTaken) {
  const Payload valid = encoded(make_pose(1, 1000));
  for (int first = 0; first < 256; ++first) {
    for (int second = 0; second < 256; ++second) {
      Payload bytes = valid;
      bytes[0] = static_cast<std::uint8_t>(first);
      bytes[1] = static_cast<std::uint8_t>(second);
      ASSERT_EQ(is_plain_cdr(bytes.data(), bytes.size()), first == 0 && second <= 1) << first << " " << second;
    }
  }
  EXPECT_FALSE(is_plain_cdr(valid.data(), 3));
  EXPECT_FALSE(is_plain_cdr(nullptr, 0));
}

TEST(DdsHostileSamples, TheArrivalWindowBoundsStampsBothWaysAndNeverOverflows) {
  const ArrivalWindow window{.source_clock_offset_ns = 0, .max_ahead_ns = 50 * kNsPerMs, .max_behind_ns = kNsPerSecond};
  const TimeNs arrival_ns = 1000 * kNsPerSecond;
  EXPECT_EQ(window.check(arrival_ns, arrival_ns), SampleFault::none);
  EXPECT_EQ(window.check(arrival_ns + 50 * kNsPerMs, arrival_ns), SampleFault::none);
  EXPECT_EQ(window.check(arrival_ns + 51 * kNsPerMs, arrival_ns), SampleFault::time_out_of_window);
  EXPECT_EQ(window.check(arrival_ns - kNsPerSecond, arrival_ns), SampleFault::none);
  EXPECT_EQ(window.check(arrival_ns - kNsPerSecond - 1, arrival_ns), SampleFault::time_out_of_window);
  for (const TimeNs extreme : {std::numeric_limits<TimeNs>::max(), std::numeric_limits<TimeNs>::min()})
    EXPECT_EQ(window.check(extreme, arrival_ns), SampleFault::time_out_of_window);
  // A device on another clock: its stamps are 7 s behind this host's.
  const ArrivalWindow offset{.source_clock_offset_ns = 7 * kNsPerSecond};
  EXPECT_EQ(offset.check(arrival_ns - 7 * kNsPerSecond, arrival_ns), SampleFault::none);
  EXPECT_EQ(offset.check(arrival_ns, arrival_ns), SampleFault::time_out_of_window);
  EXPECT_EQ(offset.check(std::numeric_limits<TimeNs>::max(), arrival_ns), SampleFault::time_out_of_window);
}

TEST(DdsHostileSamples, AFutureStampIsRefusedAndDoesNotBlindThePosesOrFramesAfterIt) {
  auto writer = DdsNode::create(local_network(194));
  auto windowed = DdsNode::create(local_network(194));
  auto unguarded = DdsNode::create(local_network(194));  // the same streams without a window: blinded
  ASSERT_TRUE(writer.ok() && windowed.ok() && unguarded.ok());
  PoseInbox windowed_poses({1}), unguarded_poses({1});
  auto windowed_frames = std::make_unique<RingSink<UltrasoundFrame, 16>>();
  auto unguarded_frames = std::make_unique<RingSink<UltrasoundFrame, 16>>();
  ASSERT_TRUE(windowed.value()->subscribe(windowed_poses, ArrivalWindow{}).ok());
  ASSERT_TRUE(windowed.value()->subscribe(*windowed_frames, ArrivalWindow{}).ok());
  ASSERT_TRUE(unguarded.value()->subscribe(unguarded_poses).ok());
  ASSERT_TRUE(unguarded.value()->subscribe(*unguarded_frames).ok());
  ASSERT_TRUE(writer.value()->advertise<ToolPose>().ok() && writer.value()->advertise<UltrasoundFrame>().ok());
  ASSERT_TRUE(writer.value()->wait_for_match(Topic::tool_pose, 2, 10 * kNsPerSecond));
  ASSERT_TRUE(writer.value()->wait_for_match(Topic::ultrasound_frame, 2, 10 * kNsPerSecond));

  const MonotonicClock clock;
  // Poses and frames are best effort: what the writer sends before a reader has matched it is
  // lost (the first pose and frame, in half the runs under the sanitizers). Warm-up samples at
  // the current time until both readers took a pose and a frame; the counts below are from then.
  ASSERT_TRUE(wait_until([&] {
    writer.value()->write(make_pose(1, clock.now_ns()));
    writer.value()->write(*make_frame(16, 8, clock.now_ns()));
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    return windowed_frames->size() >= 1 && unguarded_frames->size() >= 1 &&
           windowed.value()->boundary_counts().accepted > windowed_frames->size() &&
           unguarded.value()->boundary_counts().accepted > unguarded_frames->size();
  }));
  std::this_thread::sleep_for(std::chrono::milliseconds(100));  // the warm-up's last samples in
  for (UltrasoundFrame taken; windowed_frames->try_pop(taken) || unguarded_frames->try_pop(taken);) {
  }
  const BoundaryCounts w0 = windowed.value()->boundary_counts(), u0 = unguarded.value()->boundary_counts();
  constexpr TimeNs kFutureNs = 1'000'000 * kNsPerSecond;  // a million seconds ahead
  constexpr int kLegitimate = 6;
  for (int i = 0; i < kLegitimate; ++i) {
    ASSERT_TRUE(writer.value()->write(make_pose(1, clock.now_ns() + (i == 1 ? kFutureNs : 0))));
    ASSERT_TRUE(writer.value()->write(*make_frame(16, 8, clock.now_ns() + (i == 1 ? kFutureNs : 0))));
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  ASSERT_TRUE(wait_until([&] {
    const BoundaryCounts w = windowed.value()->boundary_counts(), u = unguarded.value()->boundary_counts();
    return w.accepted - w0.accepted + w.time_out_of_window >= 2 * kLegitimate &&
           u.accepted - u0.accepted + u.time_backwards >= 2 * kLegitimate;
  }));
  const BoundaryCounts w = windowed.value()->boundary_counts(), u = unguarded.value()->boundary_counts();
  std::printf("with the window: %s, %llu accepted; without: %s, %llu accepted (after %llu and %llu warm-up)\n",
              drops_by_reason(w).c_str(), static_cast<unsigned long long>(w.accepted - w0.accepted),
              drops_by_reason(u).c_str(), static_cast<unsigned long long>(u.accepted - u0.accepted),
              static_cast<unsigned long long>(w0.accepted), static_cast<unsigned long long>(u0.accepted));
  EXPECT_EQ(w.time_out_of_window, 2u);  // the future pose and the future frame, nothing else
  EXPECT_EQ(w.accepted - w0.accepted, 2u * (kLegitimate - 1));
  EXPECT_EQ(windowed_frames->size(), static_cast<std::size_t>(kLegitimate - 1));
  // Without it, the future stamps became the streams' time: every sample after them was dropped.
  EXPECT_EQ(u.time_backwards, 2u * (kLegitimate - 2));
}

/// Sends, `rounds` times, every crafted payload of a valid sample and then the valid sample
/// itself (valid_of_round(round), 1 ms later each round), 10 ms apart: a reader of the
/// shallowest history (frames: 2) takes each before the next. Returns the crafted payloads written.
template <typename Sample, typename ValidOfRound>
std::size_t send_rounds(RawPayloadWriter<Sample>& writer, ValidOfRound valid_of_round, int rounds) {
  std::size_t crafted_written = 0;
  for (int round = 0; round < rounds; ++round) {
    const Payload valid = encoded(valid_of_round((round + 1) * kNsPerMs));
    for (const auto& [what, bytes] : crafted_payloads(valid)) {
      if (writer.write(bytes)) ++crafted_written;
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    EXPECT_TRUE(writer.write(valid));
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return crafted_written;
}

TEST(DdsHostileSamples, AReaderCountsCraftedPayloadsFromAForeignParticipantAndKeepsTheValidOnes) {
  auto node = DdsNode::create(local_network(190));
  ASSERT_TRUE(node.ok()) << node.error().describe();
  auto poses = std::make_unique<RingSink<ToolPose, 64>>();
  ASSERT_TRUE(node.value()->subscribe(*poses).ok());
  RawPayloadWriter<ToolPose> foreign(190);
  ASSERT_TRUE(foreign.ready());
  ASSERT_TRUE(wait_until([&] { return foreign.matched() >= 1; }));

  constexpr int kRounds = 5;
  const std::size_t crafted = send_rounds(
      foreign, [](TimeNs time_ns) { return make_pose(7, time_ns); }, kRounds);
  // The last valid pose is the last sample written: nothing can replace it before it is taken.
  std::vector<ToolPose> taken;
  ASSERT_TRUE(wait_until(
      [&] {
        ToolPose pose;
        while (poses->try_pop(pose)) taken.push_back(pose);
        return !taken.empty() && taken.back().source_time_ns == kRounds * kNsPerMs;
      },
      std::chrono::seconds(5)));
  const BoundaryCounts counts = node.value()->boundary_counts();
  std::printf("crafted payloads written %zu: %s; accepted %llu\n", crafted, drops_by_reason(counts).c_str(),
              static_cast<unsigned long long>(counts.accepted));
  // Nothing crafted got through and nothing was refused for another reason than its payload.
  // On an idle host every crafted payload is counted and every valid one taken; a listener
  // slowed by a loaded host may find a sample replaced in its keep-last history before it
  // takes it (never decoded, never counted), so most, not all.
  EXPECT_EQ(counts.accepted, taken.size());
  for (std::size_t i = 0; i < taken.size(); ++i) {
    EXPECT_EQ(taken[i].tool_id, 7u);
    EXPECT_EQ(taken[i].source_time_ns % kNsPerMs, 0) << "a valid pose is stamped on a whole millisecond";
    if (i > 0) {
      EXPECT_GT(taken[i].source_time_ns, taken[i - 1].source_time_ns);
    }
  }
  EXPECT_GE(counts.malformed, crafted / 2);
  EXPECT_LE(counts.malformed, crafted);
  EXPECT_EQ(drops_by_reason(counts), "malformed " + std::to_string(counts.malformed));
}

TEST(DdsHostileSamples, NavtoolRecordKeepsRecordingThroughCraftedPayloads) {
  const std::string recording = nav::testing::temporary_path("hostile.navrec");
  ChildProcess recorder({nav::testing::executable_path("navtool"), "record", "--out", recording, "--duration-s", "120",
                         "--domain", "191"},
                        nav::testing::temporary_path("hostile_record.log"));
  ASSERT_TRUE(recorder.started());
  RawPayloadWriter<ToolPose> foreign_poses(191);
  RawPayloadWriter<UltrasoundFrame> foreign_frames(191);
  ASSERT_TRUE(foreign_poses.ready() && foreign_frames.ready());
  ASSERT_TRUE(wait_until([&] { return foreign_poses.matched() >= 1 && foreign_frames.matched() >= 1; },
                         std::chrono::seconds(30)));

  constexpr int kRounds = 4;
  const std::size_t crafted = send_rounds(
                                  foreign_poses, [](TimeNs time_ns) { return make_pose(7, time_ns); }, kRounds) +
                              send_rounds(
                                  foreign_frames, [](TimeNs time_ns) { return *make_frame(64, 48, time_ns); }, kRounds);
  std::this_thread::sleep_for(std::chrono::milliseconds(200));  // the last samples reach the file
  recorder.signal(SIGTERM);
  const std::optional<int> exit_code = recorder.wait(std::chrono::seconds(30));
  std::printf("crafted payloads written %zu\n%s", crafted, recorder.log().c_str());
  ASSERT_EQ(exit_code, 0) << "navtool record did not end by itself: " << recorder.log();
  // Best-effort and keep-last: a crafted sample replaced before the listener takes it is never
  // decoded, so never counted; most are.
  EXPECT_GE(nav::testing::number_after(recorder.log(), "malformed "), static_cast<double>(crafted) / 2);
  // The recording is intact and holds valid samples only. A valid sample may itself be replaced
  // by the crafted one after it before a slow listener (sanitizers) takes it, but the last one of
  // each topic has nothing after it: the recorder must have kept it.
  auto reader = RecordingReader::open(recording);
  ASSERT_TRUE(reader.ok()) << reader.error().describe();
  EXPECT_FALSE(reader.value()->damage().has_value());
  const std::size_t records = reader.value()->record_count();
  std::printf("valid samples recorded %zu of %d\n", records, 2 * kRounds);
  EXPECT_LE(records, 2u * kRounds);
  TimeNs last_pose_ns = 0, last_frame_ns = 0;
  for (std::size_t i = 0; i < records; ++i) {
    auto sample = reader.value()->read(i);
    ASSERT_TRUE(sample.ok()) << sample.error().describe();
    (sample.value().topic == Topic::tool_pose ? last_pose_ns : last_frame_ns) = sample.value().source_time_ns;
  }
  EXPECT_EQ(last_pose_ns, kRounds * kNsPerMs);
  EXPECT_EQ(last_frame_ns, kRounds * kNsPerMs);
  std::remove(recording.c_str());
}

TEST(DdsHostileSamples, NavstationRunsThroughCraftedAndFutureStampedSamplesAndCountsThem) {
  const std::string log = nav::testing::temporary_path("hostile_station.log");
  ChildProcess station({nav::testing::executable_path("navstation"), "--demo", "--seconds", "5", "--domain", "192"},
                       log);
  ASSERT_TRUE(station.started());
  RawPayloadWriter<ToolPose> foreign_poses(192);
  RawPayloadWriter<UltrasoundFrame> foreign_frames(192);
  ASSERT_TRUE(foreign_poses.ready() && foreign_frames.ready());
  // The station joins once it has built its scene and simulated its world (seconds).
  ASSERT_TRUE(
      wait_until([&] { return station.ended() || (foreign_poses.matched() >= 1 && foreign_frames.matched() >= 1); },
                 std::chrono::seconds(300)));
  // And a participant that keeps every rule but stamps needle poses and frames a million
  // seconds ahead, every 100 ms.
  auto stamper = DdsNode::create(local_network(192));
  ASSERT_TRUE(stamper.ok());
  ASSERT_TRUE(stamper.value()->advertise<ToolPose>().ok() && stamper.value()->advertise<UltrasoundFrame>().ok());
  const MonotonicClock clock;
  constexpr TimeNs kFutureNs = 1'000'000 * kNsPerSecond;
  const auto future_frame = make_frame(64, 48, 0);

  const auto poses = crafted_payloads(encoded(make_pose(1, 1000)));
  const auto frames = crafted_payloads(encoded(*make_frame(64, 48, 2000)));
  std::size_t written = 0;
  for (std::size_t i = 0; !station.ended() && i < 100000; ++i) {  // until the run ends (a few seconds)
    written += foreign_poses.write(poses[i % poses.size()].second) ? 1 : 0;
    written += foreign_frames.write(frames[i % frames.size()].second) ? 1 : 0;
    if (i % 10 == 0) {
      stamper.value()->write(make_pose(1, clock.now_ns() + kFutureNs));
      ToolPose far = make_pose(1, clock.now_ns());
      far.position_m = {1e300, 0.0, 0.0};  // finite, and far outside any tracker's volume
      stamper.value()->write(far);
      future_frame->source_time_ns = clock.now_ns() + kFutureNs;
      stamper.value()->write(*future_frame);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  const std::optional<int> exit_code = station.wait(std::chrono::seconds(60));
  const std::string output = station.log();
  std::printf("crafted payloads written %zu\n%s", written, output.c_str());
  ASSERT_EQ(exit_code, 0);
  EXPECT_NE(output.find("tumour now"), std::string::npos);
  EXPECT_GE(nav::testing::number_after(output, "dropped at the boundary: malformed "), 20.0);
  EXPECT_GE(nav::testing::number_after(output, "time_out_of_window "), 10.0);
  EXPECT_GE(nav::testing::number_after(output, "implausible_pose "), 10.0);
  // Each refusal that names its input is that input's: the future and far needle poses (tool 1)
  // the needle's, the future and crafted frames the ultrasound's; the probe had none.
  const std::size_t by_input = output.find("refused by input: ");
  ASSERT_NE(by_input, std::string::npos);
  const std::string inputs = output.substr(by_input, output.find('\n', by_input) - by_input);
  EXPECT_GE(nav::testing::number_after(inputs, "needle "), 20.0) << inputs;
  EXPECT_EQ(nav::testing::number_after(inputs, "probe "), 0.0) << inputs;
  EXPECT_EQ(nav::testing::number_after(inputs, "respiratory "), 0.0) << inputs;
  EXPECT_GE(nav::testing::number_after(inputs, "ultrasound "), 20.0) << inputs;
  // The simulated devices' poses (60 Hz for 3 markers, 5 s, less the time the processes take to find each other) and
  // frames (20 Hz) still arrive and are used: none is refused as older than the future stamps.
  EXPECT_EQ(output.find("time_backwards"), std::string::npos);
  EXPECT_GE(nav::testing::number_after(output, "127.0.0.1): "), 250.0);
  EXPECT_GE(nav::testing::number_after(output, "ultrasound: "), 30.0);
}

/// The lock files of the shared-memory segments process `pid` owns: those it keeps open (it
/// holds their lock through that descriptor as long as it lives).
std::set<std::string> segment_locks_of(pid_t pid) {
  std::set<std::string> locks;
  std::error_code ignored;
  for (const auto& fd : std::filesystem::directory_iterator("/proc/" + std::to_string(pid) + "/fd", ignored)) {
    const std::string target = std::filesystem::read_symlink(fd.path(), ignored).string();
    if (target.starts_with("/dev/shm/fastrtps_") && !target.starts_with("/dev/shm/fastrtps_port") &&
        target.ends_with("_el"))
      locks.insert(target);
  }
  return locks;
}

/// True when a process holds `path` locked.
bool held(const std::string& path) {
  const int fd = open(path.c_str(), O_RDONLY);
  if (fd < 0) return false;
  const bool locked = flock(fd, LOCK_EX | LOCK_NB) != 0;
  close(fd);
  return locked;
}

TEST(DdsHostileSamples, TheSegmentOfAKilledParticipantIsRemovedWhenTheNextOneStarts) {
  ChildProcess recorder({nav::testing::executable_path("navtool"), "record", "--out",
                         nav::testing::temporary_path("killed.navrec"), "--duration-s", "120", "--domain", "193"},
                        nav::testing::temporary_path("killed_record.log"));
  ASSERT_TRUE(wait_until([&] { return !segment_locks_of(recorder.pid()).empty(); }, std::chrono::seconds(30)));
  // Its lock files are opened, then locked: once it has settled, it holds every one.
  std::this_thread::sleep_for(std::chrono::seconds(1));
  const std::set<std::string> its_locks = segment_locks_of(recorder.pid());
  for (const std::string& lock : its_locks) EXPECT_TRUE(held(lock)) << lock << " not held by the live participant";
  recorder.signal(SIGKILL);
  EXPECT_FALSE(recorder.wait(std::chrono::seconds(10)).has_value());  // killed: no exit code
  for (const std::string& lock : its_locks) EXPECT_FALSE(held(lock)) << lock << " still held after the kill";
  std::this_thread::sleep_for(std::chrono::milliseconds(1200));  // older than the cleanup's 1 s guard

  // The next participant to start removes what the killed one left (or one that other tests
  // started on this host meanwhile already did): the segment and its lock file.
  auto node = DdsNode::create(local_network(193));
  ASSERT_TRUE(node.ok()) << node.error().describe();
  for (const std::string& lock : its_locks) {
    EXPECT_FALSE(std::filesystem::exists(lock)) << lock;
    EXPECT_FALSE(std::filesystem::exists(lock.substr(0, lock.size() - 3))) << "the segment of " << lock;
  }
}

TEST(DdsHostileSamples, CleanupKeepsSegmentsInUseOrJustCreatedAndOtherFiles) {
  const std::filesystem::path folder = nav::testing::temporary_path("shm");
  std::filesystem::create_directories(folder);
  const auto make = [&](const std::string& name, bool age) {
    std::ofstream(folder / name) << "x";
    if (age)
      std::filesystem::last_write_time(folder / name,
                                       std::filesystem::file_time_type::clock::now() - std::chrono::minutes(5));
  };
  for (const char* id : {"00112233445566aa", "00112233445566bb", "00112233445566cc"}) {
    make(std::string("fastrtps_") + id, true);
  }
  make("fastrtps_00112233445566aa_el", true);   // dead: removed with its segment
  make("fastrtps_00112233445566bb_el", true);   // held below: in use
  make("fastrtps_00112233445566cc_el", false);  // just created: its owner may not hold it yet
  make("fastrtps_port7411_el", true);           // a port: Fast DDS's own
  make("fastrtps_0011223344556_el", true);      // not a segment name
  const int held_fd = open((folder / "fastrtps_00112233445566bb_el").c_str(), O_RDONLY);
  ASSERT_EQ(flock(held_fd, LOCK_EX | LOCK_NB), 0);

  const SharedMemoryCleanup cleanup = remove_dead_shared_memory(folder.string());
  close(held_fd);
  EXPECT_EQ(cleanup.removed, 1u);
  EXPECT_EQ(cleanup.in_use, 2u);
  EXPECT_FALSE(std::filesystem::exists(folder / "fastrtps_00112233445566aa"));
  EXPECT_FALSE(std::filesystem::exists(folder / "fastrtps_00112233445566aa_el"));
  for (const char* kept : {"fastrtps_00112233445566bb", "fastrtps_00112233445566bb_el", "fastrtps_00112233445566cc",
                           "fastrtps_00112233445566cc_el", "fastrtps_port7411_el", "fastrtps_0011223344556_el"}) {
    EXPECT_TRUE(std::filesystem::exists(folder / kept)) << kept;
  }
  std::filesystem::remove_all(folder);
}

}  // namespace
}  // namespace nav::dds
