#pragma once
// The central-difference update shared by the explicit tissue integrators. Internal.
#include <span>

#include "nav/tissue/tet_fem_tables.hpp"

namespace nav::detail {

/// On free nodes: v = ((1 - h a / 2) v + h f / m) / (1 + h a / 2), x += h v (velocities at half
/// steps, mass-proportional damping a taken at the mid-point).
inline void central_difference_update(const TetFemTables& tables, std::span<const double> forces_n, double step_s,
                                      double damping_per_s, std::span<double> x, std::span<double> v) noexcept {
  const double half_damping = 0.5 * step_s * damping_per_s;
  for (std::int32_t node : tables.free_nodes) {
    const double inverse_mass = 1.0 / tables.mass_kg[static_cast<std::size_t>(node)];
    for (int c = 0; c < 3; ++c) {
      const std::size_t i = 3 * static_cast<std::size_t>(node) + c;
      v[i] = ((1.0 - half_damping) * v[i] + step_s * inverse_mass * forces_n[i]) / (1.0 + half_damping);
      x[i] += step_s * v[i];
    }
  }
}

}  // namespace nav::detail
