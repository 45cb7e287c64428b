#pragma once
// FNV-1a, the 64-bit hash of bytes the project uses for fingerprints, checksums and the
// bitwise-repeat checks of outputs: simple, fixed cost, the same on every architecture.
#include <cstddef>
#include <cstdint>

namespace nav {

/// The FNV-1a start value; chain fnv1a calls from it.
inline constexpr std::uint64_t kFnvOffsetBasis = 14695981039346656037ull;

/// `hash` extended by `size` bytes at `bytes`.
inline std::uint64_t fnv1a(std::uint64_t hash, const void* bytes, std::size_t size) noexcept {
  const auto* byte = static_cast<const unsigned char*>(bytes);
  for (std::size_t i = 0; i < size; ++i) hash = (hash ^ byte[i]) * 1099511628211ull;
  return hash;
}

}  // namespace nav
