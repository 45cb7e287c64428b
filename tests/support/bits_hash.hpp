#pragma once
// The tests' fingerprint of a state: the core's FNV-1a over the bytes of every given buffer,
// so that equal hashes mean bitwise-equal states (and golden hashes, the same bits on every
// architecture).
#include <cstdint>
#include <initializer_list>
#include <span>

#include "nav/core/fnv_hash.hpp"

namespace nav::testing {

/// FNV-1a over the bytes of `buffers`, in order.
inline std::uint64_t bits_hash(std::initializer_list<std::span<const double>> buffers) {
  std::uint64_t hash = kFnvOffsetBasis;
  for (std::span<const double> buffer : buffers) hash = fnv1a(hash, buffer.data(), buffer.size_bytes());
  return hash;
}

}  // namespace nav::testing
