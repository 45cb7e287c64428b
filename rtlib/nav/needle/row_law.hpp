#pragma once
// The law of a constraint row, apart from the row's geometry, and its force bound: plain
// data and one internal-linkage function that the lane kernels (needle_lane_kernels.hpp)
// use too.
#include <cstdint>

namespace nav {

/// The (gap, force) graph of a row, Duriez's characteristic graphs (section 2.5).
enum class RowLaw : std::uint8_t {
  bilateral,          ///< gap = 0, force free (path and tip lateral directions)
  unilateral_capped,  ///< gap >= 0, 0 <= force <= cap, gap <= 0 allowed at the cap
                      ///< (puncture up to f_p, cutting up to the cutting force)
  friction_axial,     ///< |force| <= cap + mu |lateral force of the two linked rows|, stick or slip
  coulomb_pair,       ///< first of two tangent rows: |(f1, f2)| <= mu * force of the linked normal row
  coulomb_second,     ///< second of those rows, solved with the first
};

/// Rows of one constraint point: at most this many, consecutive, sharing the needle point
/// (node and weight) and the tissue point. The solver and the compliance work per point.
inline constexpr int kMaxRowsPerPoint = 3;

/// The force bound of a row given the current forces (newtons): cap + mu |lateral force of
/// its two linked rows| for axial friction, mu max(0, linked normal force) for a Coulomb pair,
/// else its cap. `Row` has the fields cap, friction_coefficient, linked and law. `static`:
/// every file keeps its own copy, the lane kernels of each instruction set too, so the linker
/// never shares one between them.
template <class Row>
[[gnu::always_inline]] static inline double row_force_limit_n(const Row& row, const double* forces) {
  const auto force_of = [forces](std::int32_t linked) { return linked >= 0 ? forces[linked] : 0.0; };
  switch (row.law) {
    case RowLaw::friction_axial: {
      const double a = force_of(row.linked[0]), b = force_of(row.linked[1]);
      return row.cap + row.friction_coefficient * __builtin_sqrt(a * a + b * b);
    }
    case RowLaw::coulomb_pair:
    case RowLaw::coulomb_second: {
      const double normal = force_of(row.linked[0]);
      return row.friction_coefficient * (normal > 0.0 ? normal : 0.0);
    }
    case RowLaw::bilateral:
    case RowLaw::unilateral_capped:
      break;
  }
  return row.cap;
}

}  // namespace nav
