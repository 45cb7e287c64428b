#pragma once
// Shared helpers of the needle tests: a hash of a state for bitwise repeatability, and the
// needle parameters most tests start from.
#include <cstdint>
#include <cstring>
#include <span>

#include "nav/needle/needle_model.hpp"

namespace nav::testing {

/// FNV-1a over the bytes of every given buffer.
inline std::uint64_t needle_hash(std::initializer_list<std::span<const double>> buffers) {
  std::uint64_t hash = 1469598103934665603ull;
  for (std::span<const double> buffer : buffers)
    for (double v : buffer) {
      unsigned char bytes[sizeof(double)];
      std::memcpy(bytes, &v, sizeof(double));
      for (unsigned char byte : bytes) hash = (hash ^ byte) * 1099511628211ull;
    }
  return hash;
}

/// An 18 G steel needle of 15 cm in 20 elements, quasi-static with 5 Newton iterations.
inline NeedleParameters quasi_static_needle(BeamTheory theory = BeamTheory::euler_bernoulli) {
  NeedleParameters p;
  p.theory = theory;
  p.integrator = NeedleIntegrator::quasi_static;
  p.newton_iterations = 5;
  return p;
}

}  // namespace nav::testing
