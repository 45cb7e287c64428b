#pragma once
// The names of a set of health flags, for logs and displays (allocates: never in step code).
#include <cstdint>
#include <string>

namespace nav {

/// The names of the HealthFlag bits raised in `bits`, lowest first, space-separated ("" for none).
std::string health_flag_names(std::uint32_t bits);

}  // namespace nav
