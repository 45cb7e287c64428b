// libFuzzer target for the MetaImage label volume reader: the input is the .mha file (a
// header naming a data file reads it beside the scratch file, when there is one).
#include <cstddef>
#include <cstdint>

#include "fuzz_input_file.hpp"
#include "nav/mesher/metaimage_reader.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  nav::read_metaimage_labels(nav::fuzzing::write_input_file(data, size, ".mha"));
  return 0;
}
