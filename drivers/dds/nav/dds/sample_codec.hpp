#pragma once
// Samples as bytes: the CDR encoding of their wire type (what DDS itself sends), for
// recordings. Sample is any type of samples.hpp. I/O side only: these allocate.
#include <cstddef>
#include <cstdint>
#include <vector>

#include "nav/dds/sample_fault.hpp"
#include "nav/dds/samples.hpp"
#include "nav/dds/topics.hpp"

namespace nav::dds {

/// The topic that carries Sample.
template <typename Sample>
Topic topic_of() noexcept;

/// `sample` as CDR into `bytes` (resized); false when it exceeds the type's bounds.
template <typename Sample>
bool encode_sample(const Sample& sample, std::vector<std::uint8_t>& bytes);

/// `sample` from CDR `bytes`: none, malformed when they do not decode (checked_type.hpp, the
/// path DDS readers take too), wrong_size, or the fault check_sample() finds in the values.
template <typename Sample>
SampleFault decode_sample(const std::uint8_t* bytes, std::size_t size, Sample& sample);

}  // namespace nav::dds
