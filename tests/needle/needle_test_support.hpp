#pragma once
// Shared helpers of the needle tests: the needle parameters most tests start from (and the
// tests' state hash, support/bits_hash.hpp).
#include "nav/needle/needle_model.hpp"
#include "support/bits_hash.hpp"

namespace nav::testing {

/// The needle's insertion per tick in the insertion tests: 20 mm/s at 1 kHz.
inline constexpr double kInsertionStepM = 2e-5;

/// An 18 G steel needle of 15 cm in 20 elements, quasi-static with 5 Newton iterations.
inline NeedleParameters quasi_static_needle(BeamTheory theory = BeamTheory::euler_bernoulli) {
  NeedleParameters p;
  p.theory = theory;
  p.integrator = NeedleIntegrator::quasi_static;
  p.newton_iterations = 5;
  return p;
}

}  // namespace nav::testing
