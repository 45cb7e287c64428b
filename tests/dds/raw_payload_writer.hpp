#pragma once
// A participant of another vendor, as far as the station can tell: it joins over UDP on
// loopback only (no shared memory, no data-sharing) and writes whatever bytes a test gives it
// as the payload of a station topic, under the station's type name, encapsulation header
// included. Tests craft malformed samples with it that no Fast DDS writer of the generated
// types would produce.
#include <cstring>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <fastdds/dds/domain/DomainParticipant.hpp>
#include <fastdds/dds/domain/DomainParticipantFactory.hpp>
#include <fastdds/dds/publisher/DataWriter.hpp>
#include <fastdds/dds/publisher/Publisher.hpp>
#include <fastdds/dds/topic/TopicDataType.hpp>
#include <fastdds/dds/topic/TypeSupport.hpp>

#include "nav/dds/participant_qos.hpp"
#include "nav/dds/topic_qos.hpp"
#include "nav/dds/wire_convert.hpp"

namespace nav::dds::testing {

/// A topic type whose samples are byte vectors written to the wire as they are.
class RawPayloadType final : public eprosima::fastdds::dds::TopicDataType {
 public:
  RawPayloadType(const char* type_name, std::uint32_t max_bytes) {
    setName(type_name);
    m_typeSize = max_bytes;
  }
  bool serialize(void* data, eprosima::fastrtps::rtps::SerializedPayload_t* payload) override {
    const auto& bytes = *static_cast<const std::vector<std::uint8_t>*>(data);
    if (bytes.size() > payload->max_size) return false;
    std::memcpy(payload->data, bytes.data(), bytes.size());
    payload->length = static_cast<std::uint32_t>(bytes.size());
    return true;
  }
  bool deserialize(eprosima::fastrtps::rtps::SerializedPayload_t*, void*) override { return false; }
  std::function<std::uint32_t()> getSerializedSizeProvider(void* data) override {
    return [data] { return static_cast<std::uint32_t>(static_cast<const std::vector<std::uint8_t>*>(data)->size()); };
  }
  void* createData() override { return new std::vector<std::uint8_t>(); }
  void deleteData(void* data) override { delete static_cast<std::vector<std::uint8_t>*>(data); }
  bool getKey(void*, eprosima::fastrtps::rtps::InstanceHandle_t*, bool) override { return false; }
};

/// One UDP-only participant with a raw writer on Sample's topic (default name).
template <typename Sample>
class RawPayloadWriter {
 public:
  explicit RawPayloadWriter(std::uint32_t domain_id) {
    namespace fdds = eprosima::fastdds::dds;
    NetworkConfig network;
    network.domain_id = domain_id;
    network.participant_name = "foreign_vendor";
    network.shared_memory = false;  // UDP on 127.0.0.1 only
    auto qos = make_participant_qos(network);
    if (!qos) return;
    participant_ = fdds::DomainParticipantFactory::get_instance()->create_participant(domain_id, qos.value());
    if (participant_ == nullptr) return;
    typename WireTraits<Sample>::PubSubType generated;
    fdds::TypeSupport type(new RawPayloadType(generated.getName(), generated.m_typeSize));
    if (type.register_type(participant_) != ReturnCode_t::RETCODE_OK) return;
    constexpr Topic topic = WireTraits<Sample>::topic;
    fdds::Topic* dds_topic = participant_->create_topic(topic_name(topic), type.get_type_name(), fdds::TopicQos());
    fdds::Publisher* publisher = participant_->create_publisher(fdds::PublisherQos());
    if (dds_topic == nullptr || publisher == nullptr) return;
    TopicQosOptions options;
    options.data_sharing = false;
    writer_ = publisher->create_datawriter(dds_topic, writer_qos(topic, options));
  }
  ~RawPayloadWriter() {
    if (participant_ == nullptr) return;
    participant_->delete_contained_entities();
    eprosima::fastdds::dds::DomainParticipantFactory::get_instance()->delete_participant(participant_);
  }
  RawPayloadWriter(const RawPayloadWriter&) = delete;
  RawPayloadWriter& operator=(const RawPayloadWriter&) = delete;

  bool ready() const { return writer_ != nullptr; }
  /// Readers matched by the writer.
  int matched() const {
    eprosima::fastdds::dds::PublicationMatchedStatus status;
    writer_->get_publication_matched_status(status);
    return status.current_count;
  }
  /// Sends `payload` as one sample; false when DDS refused it.
  bool write(std::vector<std::uint8_t> payload) { return writer_->write(&payload); }

 private:
  eprosima::fastdds::dds::DomainParticipant* participant_ = nullptr;
  eprosima::fastdds::dds::DataWriter* writer_ = nullptr;
};

}  // namespace nav::dds::testing
