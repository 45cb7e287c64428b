#pragma once
// The fixed iteration count of every polar decomposition in rtlib (full-order and reduced).

namespace nav {

/// Iterations of the polar decompositions: enough for condition numbers up to about 1e8.
inline constexpr int kPolarIterations = 8;

}  // namespace nav
