// libFuzzer target for the recording reader: the input is a recording file; every record it
// locates is read and its payload decoded as the sample of its topic, as a replay does.
#include <cstddef>
#include <cstdint>
#include <memory>

#include "fuzz_input_file.hpp"
#include "nav/dds/recording_file.hpp"
#include "nav/dds/sample_codec.hpp"

namespace {

/// Decodes `record` as a Sample if it is of Sample's topic (samples live on the heap: a frame
/// is 1 MiB).
template <typename Sample>
void decode_if_of(const nav::dds::RecordedSample& record) {
  static const auto sample = std::make_unique<Sample>();
  if (record.topic == nav::dds::topic_of<Sample>())
    nav::dds::decode_sample(record.payload.data(), record.payload.size(), *sample);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  using namespace nav::dds;
  auto reader = RecordingReader::open(nav::fuzzing::write_input_file(data, size, ".navrec"));
  if (!reader.ok()) return 0;
  for (std::size_t i = 0; i < reader.value()->record_count(); ++i) {
    const auto record = reader.value()->read(i);
    if (!record.ok()) continue;
    decode_if_of<ToolPose>(record.value());
    decode_if_of<UltrasoundFrame>(record.value());
    decode_if_of<NeedleState>(record.value());
    decode_if_of<TargetPrediction>(record.value());
    decode_if_of<DeformedSurface>(record.value());
    decode_if_of<StationHealth>(record.value());
    decode_if_of<GroundTruth>(record.value());
  }
  return 0;
}
