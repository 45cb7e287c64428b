#pragma once
// The law of a constraint row, apart from the row's geometry: plain data that the lane
// kernels (needle_lane_kernels.hpp) read too.
#include <cstdint>

namespace nav {

/// The (gap, force) graph of a row, Duriez's characteristic graphs (section 2.5).
enum class RowLaw : std::uint8_t {
  bilateral,         ///< gap = 0, force free (path and tip lateral directions)
  unilateral_capped, ///< gap >= 0, 0 <= force <= cap, gap <= 0 allowed at the cap
                     ///< (puncture up to f_p, cutting up to the cutting force)
  friction_axial,    ///< |force| <= cap + mu |lateral force of the two linked rows|, stick or slip
  coulomb_pair,      ///< first of two tangent rows: |(f1, f2)| <= mu * force of the linked normal row
  coulomb_second,    ///< second of those rows, solved with the first
};

/// Rows of one constraint point: at most this many, consecutive, sharing the needle point
/// (node and weight) and the tissue point. The solver and the compliance work per point.
inline constexpr int kMaxRowsPerPoint = 3;

}  // namespace nav
