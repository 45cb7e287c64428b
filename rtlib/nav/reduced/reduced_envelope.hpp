#pragma once
// The online error indicators of a reduced model: how far its coordinates are beyond the
// training envelope, and the flags on which a ladder escalates. Shared by the model's step
// and the ladders' moves.
#include <algorithm>
#include <cmath>
#include <span>

#include "nav/core/health.hpp"

namespace nav::detail {

/// The largest |q_i| / bound_i; a direction with a zero bound (never met in training) counts
/// as twice `envelope_factor` when it moves. 0 without bounds.
inline double envelope_ratio(std::span<const double> bound, double envelope_factor,
                             std::span<const double> q) noexcept {
  double ratio = 0.0;
  for (std::size_t i = 0; i < bound.size(); ++i) {
    const double magnitude = std::abs(q[i]);
    if (bound[i] > 0.0)
      ratio = std::max(ratio, magnitude / bound[i]);
    else if (magnitude > 0.0)
      ratio = std::max(ratio, 2.0 * envelope_factor);
  }
  return ratio;
}

/// A reduced step's indicator: out of its envelope, its estimated error over its bound, or
/// undone as non-finite.
inline bool reduced_indicator_fired(HealthFlags raised) noexcept {
  return raised.has(HealthFlag::reduced_out_of_envelope) || raised.has(HealthFlag::reduced_error_over_bound) ||
         raised.has(HealthFlag::non_finite_state);
}

}  // namespace nav::detail
