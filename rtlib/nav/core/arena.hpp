#pragma once
// Fixed-capacity memory for a scene's runtime buffers: one block reserved at init, carved
// into typed spans by a bump pointer. Asking for more than was declared is an init-time
// error that says who asked, for what and how much. Nothing is ever freed one by one.
#include <cstddef>
#include <memory>
#include <new>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>

#include "nav/core/error.hpp"

namespace nav {

/// One contiguous block reserved once; typed, aligned, zero-initialised spans are carved
/// from it at init. The block never grows and never moves.
class Arena {
 public:
  /// Reserves `capacity_bytes` (one allocation). `name` appears in error messages.
  Arena(std::string name, std::size_t capacity_bytes);

  Arena(const Arena&) = delete;
  Arena& operator=(const Arena&) = delete;
  Arena(Arena&&) noexcept = default;
  Arena& operator=(Arena&&) noexcept = default;

  /// A span of `count` value-initialised T, aligned for T (or to `alignment_bytes` when that is
  /// larger, a power of two: whole cache lines for wide loads), or an Error naming `what`, the
  /// bytes asked for and the bytes left. Init-time only.
  template <typename T>
  Result<std::span<T>> allocate(std::string_view what, std::size_t count, std::size_t alignment_bytes = alignof(T)) {
    static_assert(std::is_trivially_destructible_v<T>, "arena memory is never destroyed element-wise");
    auto bytes = reserve(what, count, sizeof(T), alignment_bytes > alignof(T) ? alignment_bytes : alignof(T));
    if (!bytes.ok()) return bytes.error();
    T* first = reinterpret_cast<T*>(bytes.value());
    std::uninitialized_value_construct_n(first, count);
    return std::span<T>(std::launder(first), count);
  }

  std::size_t capacity_bytes() const { return capacity_bytes_; }
  std::size_t used_bytes() const { return used_bytes_; }
  std::size_t remaining_bytes() const { return capacity_bytes_ - used_bytes_; }
  const std::string& name() const { return name_; }

 private:
  Result<std::byte*> reserve(std::string_view what, std::size_t count, std::size_t size, std::size_t alignment);

  std::string name_;
  std::size_t capacity_bytes_;
  std::size_t used_bytes_ = 0;
  std::unique_ptr<std::byte[]> block_;
};

/// Adds up the bytes a set of buffers will need in an Arena (with alignment padding), so
/// that a model can declare its footprint before anything is reserved.
class ArenaPlan {
 public:
  /// `count` T aligned as Arena::allocate() aligns them.
  template <typename T>
  ArenaPlan& add(std::size_t count, std::size_t alignment_bytes = alignof(T)) {
    const std::size_t alignment = alignment_bytes > alignof(T) ? alignment_bytes : alignof(T);
    bytes_ = round_up(bytes_, alignment) + count * sizeof(T);
    worst_alignment_padding_ += alignment - 1;
    return *this;
  }
  /// Bytes enough for every add()ed buffer, whatever the block's own alignment.
  std::size_t bytes() const { return bytes_ + worst_alignment_padding_; }

 private:
  static std::size_t round_up(std::size_t value, std::size_t alignment) {
    return (value + alignment - 1) / alignment * alignment;
  }
  std::size_t bytes_ = 0;
  std::size_t worst_alignment_padding_ = 0;
};

}  // namespace nav
