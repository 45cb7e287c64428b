#pragma once
// For fuzz targets whose parser reads a path rather than bytes: the input written to a
// scratch file of this process.
#include <cstddef>
#include <cstdint>
#include <string>

namespace nav::fuzzing {

/// Writes `size` bytes to this process's scratch file for `extension` (".mha"), replacing
/// what the previous input left there, and returns its path. Aborts if it cannot write.
const std::string& write_input_file(const std::uint8_t* data, std::size_t size, const std::string& extension);

}  // namespace nav::fuzzing
