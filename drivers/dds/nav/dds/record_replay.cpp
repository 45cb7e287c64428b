#include "nav/dds/record_replay.hpp"

#include <array>

#include "nav/dds/sample_codec.hpp"

namespace nav::dds {
namespace {

constexpr TimeNs kSettleNs = 100 * kNsPerMs;
constexpr TimeNs kAcknowledgmentTimeoutNs = 5 * kNsPerSecond;

/// Calls `visit` with a null pointer of every sample type, in topic order.
template <typename Visit>
void for_each_sample_type(Visit visit) {
  visit(static_cast<ToolPose*>(nullptr));
  visit(static_cast<UltrasoundFrame*>(nullptr));
  visit(static_cast<NeedleState*>(nullptr));
  visit(static_cast<TargetPrediction*>(nullptr));
  visit(static_cast<DeformedSurface*>(nullptr));
  visit(static_cast<StationHealth*>(nullptr));
  visit(static_cast<GroundTruth*>(nullptr));
  visit(static_cast<NeedleForce*>(nullptr));
}

/// Decodes `record` as Sample and writes it; false when it does not decode or DDS refuses.
template <typename Sample>
bool publish_record(const RecordedSample& record, DdsNode& node) {
  auto sample = std::make_unique<Sample>();
  if (decode_sample(record.payload.data(), record.payload.size(), *sample) != SampleFault::none) return false;
  return node.write(*sample);
}

/// Creates `sink` and subscribes it on `node`, unless an earlier subscription failed.
template <typename Sink>
void make_and_subscribe(DdsNode& node, std::unique_ptr<Sink>& sink, Status& status) {
  sink = std::make_unique<Sink>();
  if (status) status = node.subscribe(*sink);
}

}  // namespace

Result<std::unique_ptr<Recorder>> Recorder::create(DdsNode& node, const std::string& path) {
  std::unique_ptr<Recorder> recorder(new Recorder());
  auto writer = RecordingWriter::create(path);
  if (!writer) return writer.error();
  recorder->writer_ = std::move(writer).value();
  Status subscribed = Done{};
  std::apply([&](auto&... sinks) { (make_and_subscribe(node, sinks, subscribed), ...); }, recorder->sinks_);
  if (!subscribed) return subscribed.error();
  return recorder;
}

template <typename Sample>
Result<std::size_t> Recorder::pump_one(RingSink<Sample, kRecorderQueueDepth>& sink) {
  auto sample = std::make_unique<Sample>();
  std::size_t written = 0;
  while (sink.try_pop(*sample)) {
    if (!encode_sample(*sample, bytes_)) continue;
    const Status appended =
        writer_->append(topic_of<Sample>(), sample->source_time_ns, sample->receive_time_ns, bytes_);
    if (!appended) return appended.error();
    ++written;
  }
  return written;
}

Result<std::size_t> Recorder::pump() {
  std::size_t written = 0;
  std::optional<Error> failure;
  const auto pump_sink = [&](auto& sink) {
    if (failure) return;
    auto count = pump_one(*sink);
    if (count) {
      written += count.value();
    } else {
      failure = count.error();
    }
  };
  std::apply([&](auto&... sinks) { (pump_sink(sinks), ...); }, sinks_);
  if (failure) return *failure;
  return written;
}

ReplayReport replay(RecordingReader& recording, DdsNode& node, ReplayPace pace, TimeNs wait_for_readers_ns) {
  ReplayReport report;
  MonotonicClock clock;
  TimeNs start_ns = clock.now_ns();
  std::optional<TimeNs> first_receive_ns;
  std::array<bool, kTopicCount> advertised{};
  for (std::size_t i = 0; i < recording.record_count(); ++i) {
    auto record = recording.read(i);
    if (!record) {
      ++report.skipped;
      if (!report.first_damage) report.first_damage = record.error();
      continue;
    }
    const RecordedSample& sample = record.value();
    bool published = false;
    for_each_sample_type([&](auto* type) {
      using Sample = std::remove_pointer_t<decltype(type)>;
      if (sample.topic != topic_of<Sample>()) return;
      bool& ready = advertised[static_cast<std::size_t>(sample.topic)];
      if (!ready) {  // first record of this topic: advertise and give readers time to match
        const TimeNs waited_from_ns = clock.now_ns();
        ready = node.advertise<Sample>().ok();
        // Our writer matching a reader precedes that reader matching us; best-effort
        // samples sent in between would be lost, so let discovery settle a little.
        if (node.wait_for_match(sample.topic, 1, wait_for_readers_ns)) clock.sleep_until_ns(clock.now_ns() + kSettleNs);
        start_ns += clock.now_ns() - waited_from_ns;
      }
      if (!first_receive_ns) first_receive_ns = sample.receive_time_ns;
      if (pace == ReplayPace::recorded) clock.sleep_until_ns(start_ns + (sample.receive_time_ns - *first_receive_ns));
      published = publish_record<Sample>(sample, node);
    });
    published ? ++report.published : ++report.skipped;
  }
  report.acknowledged = node.wait_for_acknowledgments(kAcknowledgmentTimeoutNs);
  return report;
}

}  // namespace nav::dds
