// libFuzzer target for the PLUS sequence reader: the input is a whole sequence file, parsed
// both as a MetaImage (.mha) and as an NRRD (.nrrd); at most four frames' pixels are read so
// that a small compressed input cannot ask for gigabytes.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "nav/ultrasound/plus_sequence.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view bytes(reinterpret_cast<const char*>(data), size);
  const nav::ultrasound::PlusReadOptions options{.max_frames = 4};
  nav::ultrasound::parse_plus_sequence(bytes, "fuzz.mha", options);
  nav::ultrasound::parse_plus_sequence(bytes, "fuzz.nrrd", options);
  return 0;
}
