#include "nav/core/units.hpp"

namespace nav {

std::optional<LengthUnit> parse_length_unit(std::string_view text) {
  if (text == "m") return LengthUnit::metre;
  if (text == "cm") return LengthUnit::centimetre;
  if (text == "mm") return LengthUnit::millimetre;
  return std::nullopt;
}

}  // namespace nav
