#pragma once
// Internal (includes Fast DDS and the generated types): the one path by which any payload that
// arrives from outside becomes a wire sample. Fast DDS calls a topic type's deserialize() on
// its receive threads; the generated one throws Fast CDR's exceptions on a payload it does not
// expect (an unknown encapsulation, a bad first byte), and an exception there ends the process.
// Here every such payload is a counted refusal instead: Fast DDS then drops the change and
// goes on with the next.
#include <cstring>

#include <fastcdr/exceptions/Exception.h>
#include <fastdds/rtps/common/SerializedPayload.h>

#include "nav/dds/sample_fault.hpp"
#include "nav/dds/wire_convert.hpp"

namespace nav::dds {

/// The encapsulations the station's types are written in: XCDR1 plain CDR, big or little
/// endian (RTPS encapsulation identifiers 0x0000 and 0x0001; the two option bytes are free).
bool is_plain_cdr(const std::uint8_t* payload, std::size_t size) noexcept;

/// Decodes `payload` into `wire` with the generated type support `type`: none, or malformed
/// (not plain CDR, truncated, a length past its end: whatever the decoder refuses or throws),
/// or wrong_size (larger than the type's bound). Never throws.
template <typename Sample>
SampleFault checked_deserialize(typename WireTraits<Sample>::PubSubType& type,
                                eprosima::fastrtps::rtps::SerializedPayload_t& payload,
                                typename WireTraits<Sample>::Wire& wire) noexcept {
  using Generated [[maybe_unused]] =
      typename WireTraits<Sample>::PubSubType;  // clang does not count the qualified call below as a use
  if (!is_plain_cdr(payload.data, payload.length)) return SampleFault::malformed;
  if (payload.length > type.m_typeSize) return SampleFault::wrong_size;
  try {
    // The generated decoder itself, also when `type` is a CheckedPubSubType.
    return type.Generated::deserialize(&payload, &wire) ? SampleFault::none : SampleFault::malformed;
  } catch (const eprosima::fastcdr::exception::Exception&) {  // BadParamException, NotEnoughMemoryException
    return SampleFault::malformed;
  } catch (...) {  // anything else the generated code may throw (std::bad_alloc on a huge length)
    return SampleFault::malformed;
  }
}

/// The type support DDS readers and writers of Sample's topic use: the generated one, whose
/// deserialize() goes through checked_deserialize() and counts each refusal in `counters`
/// (which must outlive the participant the type is registered with).
template <typename Sample>
class CheckedPubSubType final : public WireTraits<Sample>::PubSubType {
 public:
  explicit CheckedPubSubType(BoundaryCounters& counters) : counters_(counters) {}

  /// A payload shared with a writer of this host (data sharing) lives in that writer's pool,
  /// which the writer reuses when it writes again: read while it is overwritten, it may not
  /// decode (Fast DDS drops such a sample, as it drops the overwritten ones that do). So the
  /// payload is decoded from a copy; a copy that does not decode and differs from the payload
  /// after the attempt was torn by its writer, which is not counted as sent malformed.
  bool deserialize(eprosima::fastrtps::rtps::SerializedPayload_t* payload, void* data) override {
    thread_local eprosima::fastrtps::rtps::SerializedPayload_t copy(this->m_typeSize);
    const bool copied = payload->data != nullptr && payload->length <= copy.max_size;
    if (copied) {
      std::memcpy(copy.data, payload->data, payload->length);
      copy.length = payload->length;
      copy.encapsulation = payload->encapsulation;
      copy.pos = 0;
    }
    const SampleFault fault = checked_deserialize<Sample>(*this, copied ? copy : *payload,
                                                          *static_cast<typename WireTraits<Sample>::Wire*>(data));
    if (fault == SampleFault::none) return true;
    if (copied && std::memcmp(copy.data, payload->data, copy.length) != 0)
      return false;  // torn by its writer while copied
    counters_.count(fault);
    return false;
  }

 private:
  BoundaryCounters& counters_;
};

}  // namespace nav::dds
