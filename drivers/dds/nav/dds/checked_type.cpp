#include "nav/dds/checked_type.hpp"

namespace nav::dds {

bool is_plain_cdr(const std::uint8_t* payload, std::size_t size) noexcept {
  constexpr std::size_t kEncapsulationBytes = 4;  // identifier (2 bytes, big endian), options (2)
  return payload != nullptr && size >= kEncapsulationBytes && payload[0] == 0x00 && payload[1] <= 0x01;
}

}  // namespace nav::dds
