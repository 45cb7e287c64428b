#pragma once
// The iteration bounds of every polar decomposition in rtlib (full-order and reduced).

namespace nav {

/// Most iterations of the polar decompositions: enough for condition numbers up to about 1e8.
inline constexpr int kPolarIterations = 8;

/// Iterations every matrix gets; from the last of them on, a matrix stops once no entry
/// changed by more than kPolarConvergedChange in an iteration. The scaled Newton iteration
/// converges quadratically, so the iterate after such a change is orthogonal to rounding; the
/// test sees only the iterates, so it decides alike on every instruction set, and a matrix's
/// result does not depend on the others decomposed with it.
inline constexpr int kPolarFirstIterations = 4;
inline constexpr double kPolarConvergedChange = 1e-9;

}  // namespace nav
