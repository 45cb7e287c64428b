#include "nav/dds/sample_codec.hpp"

#include <cstring>

#include "nav/dds/checked_type.hpp"
#include "nav/dds/sample_checks.hpp"
#include "nav/dds/wire_convert.hpp"

namespace nav::dds {

template <typename Sample>
Topic topic_of() noexcept {
  return WireTraits<Sample>::topic;
}

template <typename Sample>
bool encode_sample(const Sample& sample, std::vector<std::uint8_t>& bytes) {
  typename WireTraits<Sample>::PubSubType type;
  typename WireTraits<Sample>::Wire wire;
  to_wire(sample, wire);
  eprosima::fastrtps::rtps::SerializedPayload_t payload(type.m_typeSize);
  if (!type.serialize(&wire, &payload)) return false;
  bytes.assign(payload.data, payload.data + payload.length);
  return true;
}

template <typename Sample>
SampleFault decode_sample(const std::uint8_t* bytes, std::size_t size, Sample& sample) {
  typename WireTraits<Sample>::PubSubType type;
  if (!is_plain_cdr(bytes, size)) return SampleFault::malformed;  // also: empty, no buffer to copy into
  if (size > type.m_typeSize) return SampleFault::wrong_size;
  eprosima::fastrtps::rtps::SerializedPayload_t payload(static_cast<std::uint32_t>(size));
  std::memcpy(payload.data, bytes, size);
  payload.length = static_cast<std::uint32_t>(size);
  typename WireTraits<Sample>::Wire wire;
  SampleFault fault = checked_deserialize<Sample>(type, payload, wire);
  if (fault == SampleFault::none) fault = from_wire(wire, sample);
  return fault != SampleFault::none ? fault : check_sample(sample);
}

#define NAV_DDS_CODEC_SAMPLE(Sample)                                              \
  template Topic topic_of<Sample>() noexcept;                                     \
  template bool encode_sample<Sample>(const Sample&, std::vector<std::uint8_t>&); \
  template SampleFault decode_sample<Sample>(const std::uint8_t*, std::size_t, Sample&);
NAV_DDS_CODEC_SAMPLE(ToolPose)
NAV_DDS_CODEC_SAMPLE(UltrasoundFrame)
NAV_DDS_CODEC_SAMPLE(NeedleState)
NAV_DDS_CODEC_SAMPLE(TargetPrediction)
NAV_DDS_CODEC_SAMPLE(DeformedSurface)
NAV_DDS_CODEC_SAMPLE(StationHealth)
NAV_DDS_CODEC_SAMPLE(GroundTruth)
NAV_DDS_CODEC_SAMPLE(NeedleForce)
#undef NAV_DDS_CODEC_SAMPLE

}  // namespace nav::dds
