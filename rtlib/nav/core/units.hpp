#pragma once
// Length units of files read or written at init time. Everything inside is SI (metres).
#include <optional>
#include <string_view>

namespace nav {

/// The length unit of a file's coordinates; loaders scale to metres with it.
enum class LengthUnit { metre, centimetre, millimetre };

/// Metres per one unit: 1, 0.01 or 0.001.
constexpr double metres_per_unit(LengthUnit unit) {
  switch (unit) {
    case LengthUnit::centimetre:
      return 0.01;
    case LengthUnit::millimetre:
      return 0.001;
    case LengthUnit::metre:
      break;
  }
  return 1.0;
}

/// Parses "m", "cm" or "mm"; anything else gives nullopt.
std::optional<LengthUnit> parse_length_unit(std::string_view text);

}  // namespace nav
