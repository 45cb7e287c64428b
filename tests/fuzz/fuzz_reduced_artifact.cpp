// libFuzzer target for the reduced-basis artifact reader: the input is an artifact's bytes,
// decoded as navtool's loader does (without a mesh to check against, so that every check of
// the file itself is reached).
#include <cstddef>
#include <cstdint>
#include <span>

#include "nav/reduced/reduced_artifact.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto basis = nav::decode_reduced_basis(std::span<const std::uint8_t>(data, size), "fuzz input", nullptr);
  if (basis.ok() && basis.value().basis.size() != 3 * static_cast<std::size_t>(basis.value().node_count) *
                                                      static_cast<std::size_t>(basis.value().basis_size))
    __builtin_trap();  // an accepted basis must have the dimensions it declares
  return 0;
}
