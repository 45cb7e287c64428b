#include "nav/core/arena.hpp"

#include <cstdint>

namespace nav {

Arena::Arena(std::string name, std::size_t capacity_bytes)
    : name_(std::move(name)), capacity_bytes_(capacity_bytes), block_(new std::byte[capacity_bytes]) {}

Result<std::byte*> Arena::reserve(std::string_view what, std::size_t count, std::size_t size, std::size_t alignment) {
  const auto base = reinterpret_cast<std::uintptr_t>(block_.get());
  const std::size_t start = ((base + used_bytes_ + alignment - 1) / alignment * alignment) - base;
  const bool overflows = size != 0 && count > (static_cast<std::size_t>(-1) - start) / size;
  if (overflows || start + count * size > capacity_bytes_) {
    return Error{.message = "asked for " + std::to_string(count) + " x " + std::to_string(size) + " bytes for '" +
                            std::string(what) + "' but only " + std::to_string(remaining_bytes()) + " of " +
                            std::to_string(capacity_bytes_) + " bytes are left",
                 .field = "arena '" + name_ + "'"};
  }
  used_bytes_ = start + count * size;
  return block_.get() + start;
}

}  // namespace nav
