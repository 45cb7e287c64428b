#include "nav/dds/dds_node.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <mutex>
#include <thread>
#include <type_traits>

#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/subscriber/DataReader.hpp>
#include <fastdds/dds/subscriber/DataReaderListener.hpp>
#include <fastdds/dds/subscriber/SampleInfo.hpp>
#include <fastdds/dds/subscriber/Subscriber.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>

#include "nav/dds/checked_type.hpp"
#include "nav/dds/environment_guard.hpp"
#include "nav/dds/participant_qos.hpp"
#include "nav/dds/sample_boundary.hpp"
#include "nav/dds/sample_checks.hpp"
#include "nav/dds/shared_memory_cleanup.hpp"
#include "nav/dds/topic_qos.hpp"
#include "nav/dds/wire_convert.hpp"

namespace nav::dds {
namespace {

namespace fdds = eprosima::fastdds::dds;

constexpr std::size_t index_of(Topic topic) noexcept { return static_cast<std::size_t>(topic); }

/// Owns per-topic state of any sample type.
struct TopicState {
  virtual ~TopicState() = default;
};

/// The wire sample a writer serializes from, reused for every write of its topic.
template <typename Sample>
struct WriteScratch final : TopicState {
  typename WireTraits<Sample>::Wire wire;
};

/// Validates what a reader receives and offers it to a sink. Fast DDS may call
/// on_data_available from several transport threads, so the producer side of the
/// hand-off is serialized here (an I/O-side lock the real-time thread never takes).
template <typename Sample>
class SinkListener final : public fdds::DataReaderListener, public TopicState {
 public:
  SinkListener(SampleSink<Sample>& sink, BoundaryCounters& counters, std::optional<ArrivalWindow> window)
      : sink_(sink), counters_(counters), boundary_(window), sample_(std::make_unique<Sample>()) {}

  void on_data_available(fdds::DataReader* reader) override {
    const std::lock_guard<std::mutex> lock(mutex_);
    fdds::SampleInfo info;
    while (reader->take_next_sample(&wire_, &info) == ReturnCode_t::RETCODE_OK) {
      if (info.valid_data) counters_.count(accept());
    }
  }

 private:
  SampleFault accept() noexcept {
    const TimeNs arrival_ns = clock_.now_ns();
    SampleFault fault = from_wire(wire_, *sample_);
    if (fault != SampleFault::none) return fault;
    fault = boundary_.admit(*sample_, arrival_ns);
    if (fault != SampleFault::none) {
      sink_.on_refused(*sample_, fault);
      return fault;
    }
    sample_->receive_time_ns = arrival_ns;
    return sink_.offer(*sample_);
  }

  SampleSink<Sample>& sink_;
  BoundaryCounters& counters_;
  SampleBoundary<Sample> boundary_;
  std::mutex mutex_;
  typename WireTraits<Sample>::Wire wire_;
  std::unique_ptr<Sample> sample_;  // on the heap: a frame is 1 MiB
  MonotonicClock clock_;
};

}  // namespace

/// The participant, its entities and the listeners' state.
struct DdsNode::Impl {
  TopicQosOptions qos;
  BoundaryCounters counters;                                                    ///< over every topic
  std::array<std::unique_ptr<BoundaryCounters>, kTopicCount> topic_counters{};  ///< each counting into counters
  std::array<std::unique_ptr<TopicState>, kTopicCount> write_scratch{};
  std::array<std::unique_ptr<TopicState>, kTopicCount> listeners{};
  fdds::DomainParticipant* participant = nullptr;
  fdds::Publisher* publisher = nullptr;
  fdds::Subscriber* subscriber = nullptr;
  std::array<fdds::Topic*, kTopicCount> topics{};
  std::array<fdds::DataWriter*, kTopicCount> writers{};
  std::array<fdds::DataReader*, kTopicCount> readers{};

  /// Deletes the DDS entities first: no listener may run once the members go.
  ~Impl() {
    if (participant == nullptr) return;
    participant->delete_contained_entities();
    fdds::DomainParticipantFactory::get_instance()->delete_participant(participant);
  }

  template <typename Sample>
  bool create_topic() {
    constexpr Topic topic = WireTraits<Sample>::topic;
    topic_counters[index_of(topic)] = std::make_unique<BoundaryCounters>(counters);
    fdds::TypeSupport type(new CheckedPubSubType<Sample>(*topic_counters[index_of(topic)]));
    if (type.register_type(participant) != ReturnCode_t::RETCODE_OK) return false;
    topics[index_of(topic)] =
        participant->create_topic(topic_name(topic, qos.names), type.get_type_name(), fdds::TopicQos());
    return topics[index_of(topic)] != nullptr;
  }

  bool create_topics() {
    return create_topic<ToolPose>() && create_topic<UltrasoundFrame>() && create_topic<NeedleState>() &&
           create_topic<TargetPrediction>() && create_topic<DeformedSurface>() && create_topic<StationHealth>() &&
           create_topic<GroundTruth>() && create_topic<NeedleForce>();
  }
};

Result<std::unique_ptr<DdsNode>> DdsNode::create(const NetworkConfig& network, const TopicQosOptions& qos) {
  if (const Status environment = refuse_environment_overrides(); !environment) return environment.error();
  auto participant_qos = make_participant_qos(network);
  if (!participant_qos) return participant_qos.error();
  if (network.shared_memory) remove_dead_shared_memory();
  auto impl = std::make_unique<Impl>();
  impl->qos = qos;
  // Data sharing hands samples over in shared buffers, outside the RTPS messages that DDS
  // Security authenticates and encrypts: a secured participant sends everything through them.
  if (network.security.enabled()) impl->qos.data_sharing = false;
  impl->participant = fdds::DomainParticipantFactory::get_instance()->create_participant(
      static_cast<fdds::DomainId_t>(network.domain_id), participant_qos.value());
  if (impl->participant == nullptr) {
    return Error{.message = "Fast DDS refused to create the participant",
                 .field = "domain " + std::to_string(network.domain_id)};
  }
  impl->publisher = impl->participant->create_publisher(fdds::PublisherQos());
  impl->subscriber = impl->participant->create_subscriber(fdds::SubscriberQos());
  if (impl->publisher == nullptr || impl->subscriber == nullptr || !impl->create_topics()) {
    return Error{.message = "Fast DDS refused to create the station's topics"};
  }
  return std::unique_ptr<DdsNode>(new DdsNode(std::move(impl)));
}

DdsNode::DdsNode(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
DdsNode::~DdsNode() = default;

template <typename Sample>
Status DdsNode::advertise() {
  constexpr std::size_t i = index_of(WireTraits<Sample>::topic);
  if (impl_->writers[i] != nullptr)
    return Error{.message = "topic already advertised", .field = topic_name(WireTraits<Sample>::topic)};
  auto scratch = std::make_unique<WriteScratch<Sample>>();
  if constexpr (std::is_same_v<Sample, UltrasoundFrame>) scratch->wire.pixels().reserve(kMaxFramePixels);
  impl_->writers[i] =
      impl_->publisher->create_datawriter(impl_->topics[i], writer_qos(WireTraits<Sample>::topic, impl_->qos));
  if (impl_->writers[i] == nullptr)
    return Error{.message = "Fast DDS refused the writer", .field = topic_name(WireTraits<Sample>::topic)};
  impl_->write_scratch[i] = std::move(scratch);
  return Done{};
}

template <typename Sample>
bool DdsNode::write(const Sample& sample) {
  constexpr std::size_t i = index_of(WireTraits<Sample>::topic);
  if (impl_->writers[i] == nullptr) return false;
  auto& wire = static_cast<WriteScratch<Sample>&>(*impl_->write_scratch[i]).wire;
  to_wire(sample, wire);
  return impl_->writers[i]->write(&wire);
}

template <typename Sample>
Status DdsNode::subscribe(SampleSink<Sample>& sink, std::optional<ArrivalWindow> window) {
  constexpr std::size_t i = index_of(WireTraits<Sample>::topic);
  if (impl_->readers[i] != nullptr)
    return Error{.message = "topic already subscribed", .field = topic_name(WireTraits<Sample>::topic)};
  auto listener = std::make_unique<SinkListener<Sample>>(sink, *impl_->topic_counters[i], window);
  impl_->readers[i] = impl_->subscriber->create_datareader(
      impl_->topics[i], reader_qos(WireTraits<Sample>::topic, impl_->qos), listener.get());
  if (impl_->readers[i] == nullptr)
    return Error{.message = "Fast DDS refused the reader", .field = topic_name(WireTraits<Sample>::topic)};
  impl_->listeners[i] = std::move(listener);
  return Done{};
}

std::size_t DdsNode::matched(Topic topic) const {
  std::size_t count = 0;
  if (const fdds::DataWriter* writer = impl_->writers[index_of(topic)]) {
    fdds::PublicationMatchedStatus status;
    writer->get_publication_matched_status(status);
    count += static_cast<std::size_t>(status.current_count);
  }
  if (const fdds::DataReader* reader = impl_->readers[index_of(topic)]) {
    fdds::SubscriptionMatchedStatus status;
    reader->get_subscription_matched_status(status);
    count += static_cast<std::size_t>(status.current_count);
  }
  return count;
}

bool DdsNode::wait_for_match(Topic topic, std::size_t count, TimeNs timeout_ns) const {
  const MonotonicClock clock;
  const TimeNs deadline_ns = clock.now_ns() + timeout_ns;
  while (matched(topic) < count) {
    if (clock.now_ns() >= deadline_ns) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return true;
}

bool DdsNode::wait_for_acknowledgments(TimeNs timeout_ns) const {
  const MonotonicClock clock;
  const TimeNs deadline_ns = clock.now_ns() + timeout_ns;
  bool all_acknowledged = true;
  for (fdds::DataWriter* writer : impl_->writers) {
    if (writer == nullptr) continue;
    const TimeNs left_ns = std::max<TimeNs>(0, deadline_ns - clock.now_ns());
    const eprosima::fastrtps::Duration_t left(static_cast<std::int32_t>(left_ns / kNsPerSecond),
                                              static_cast<std::uint32_t>(left_ns % kNsPerSecond));
    all_acknowledged = writer->wait_for_acknowledgments(left) == eprosima::fastrtps::types::ReturnCode_t::RETCODE_OK &&
                       all_acknowledged;
  }
  return all_acknowledged;
}

BoundaryCounts DdsNode::boundary_counts() const noexcept { return impl_->counters.snapshot(); }

BoundaryCounts DdsNode::boundary_counts(Topic topic) const noexcept {
  const std::unique_ptr<BoundaryCounters>& counters = impl_->topic_counters[index_of(topic)];
  return counters ? counters->snapshot() : BoundaryCounts{};
}

std::uint64_t DdsNode::samples_lost(Topic topic) const {
  fdds::DataReader* reader = impl_->readers[index_of(topic)];
  if (reader == nullptr) return 0;
  fdds::SampleLostStatus status;
  reader->get_sample_lost_status(status);
  return static_cast<std::uint64_t>(status.total_count);
}

#define NAV_DDS_NODE_SAMPLE(Sample)                    \
  template Status DdsNode::advertise<Sample>();        \
  template bool DdsNode::write<Sample>(const Sample&); \
  template Status DdsNode::subscribe<Sample>(SampleSink<Sample>&, std::optional<ArrivalWindow>);
NAV_DDS_NODE_SAMPLE(ToolPose)
NAV_DDS_NODE_SAMPLE(UltrasoundFrame)
NAV_DDS_NODE_SAMPLE(NeedleState)
NAV_DDS_NODE_SAMPLE(TargetPrediction)
NAV_DDS_NODE_SAMPLE(DeformedSurface)
NAV_DDS_NODE_SAMPLE(StationHealth)
NAV_DDS_NODE_SAMPLE(GroundTruth)
NAV_DDS_NODE_SAMPLE(NeedleForce)
#undef NAV_DDS_NODE_SAMPLE

}  // namespace nav::dds
