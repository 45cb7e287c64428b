// libFuzzer target for the decoding of DDS samples, the path every reader's payload takes
// (checked_type.hpp): the first byte picks the topic type, the rest is the payload as it
// arrives (encapsulation identifier and options first). Any payload must decode or be refused
// without a crash; one that decodes must encode again, and that encoding must decode to the
// same bytes again (a check the fuzzer can fail).
#include <cstddef>
#include <cstdint>
#include <memory>
#include <vector>

#include "nav/dds/sample_codec.hpp"

namespace {

using namespace nav::dds;

/// Decodes `bytes` as a Sample; traps when an accepted sample does not survive a round trip.
template <typename Sample>
void decode_as(const std::uint8_t* bytes, std::size_t size) {
  static const auto sample = std::make_unique<Sample>();  // on the heap: a frame is 1 MiB
  static const auto again = std::make_unique<Sample>();
  if (decode_sample(bytes, size, *sample) != SampleFault::none) return;
  std::vector<std::uint8_t> encoded, reencoded;
  if (!encode_sample(*sample, encoded)) __builtin_trap();
  if (decode_sample(encoded.data(), encoded.size(), *again) != SampleFault::none) __builtin_trap();
  if (!encode_sample(*again, reencoded) || reencoded != encoded) __builtin_trap();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size == 0) return 0;
  const std::uint8_t* payload = data + 1;
  const std::size_t payload_size = size - 1;
  switch (data[0] % kTopicCount) {
    case 0:
      decode_as<ToolPose>(payload, payload_size);
      break;
    case 1:
      decode_as<UltrasoundFrame>(payload, payload_size);
      break;
    case 2:
      decode_as<NeedleState>(payload, payload_size);
      break;
    case 3:
      decode_as<TargetPrediction>(payload, payload_size);
      break;
    case 4:
      decode_as<DeformedSurface>(payload, payload_size);
      break;
    case 5:
      decode_as<StationHealth>(payload, payload_size);
      break;
    case 6:
      decode_as<GroundTruth>(payload, payload_size);
      break;
    default:
      decode_as<NeedleForce>(payload, payload_size);
      break;
  }
  return 0;
}
