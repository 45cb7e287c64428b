#pragma once
// Whether a state holds only finite numbers: the check every step function makes before it
// lets a state out (a NaN or an infinity raises non_finite_state). Reads every value, at a
// fixed cost whatever it finds; no allocation.
#include <cmath>
#include <span>

namespace nav {

/// True when every value is finite.
inline bool all_finite(std::span<const double> values) noexcept {
  bool finite = true;
  for (double value : values) finite = finite && std::isfinite(value);
  return finite;
}

}  // namespace nav
