#pragma once
// Step-time fault reporting: step functions never throw, allocate or abort; they raise
// health flags and degrade predictably. The flags are a plain bit set, cheap to copy and
// to publish.
#include <cstdint>

namespace nav {

/// One kind of step-time fault. Values are bits of HealthFlags.
enum class HealthFlag : std::uint32_t {
  non_finite_state = 1u << 0,           // NaN or infinity met in a state; the step was rejected
  inverted_element = 1u << 1,           // an element turned inside out
  stale_input = 1u << 2,                // an input is older than its allowed age
  missing_input = 1u << 3,              // an input never arrived or stopped arriving
  pool_full = 1u << 4,                  // a preallocated pool could not take a new entry
  buffer_overrun = 1u << 5,             // a ring dropped data because its reader fell behind
  solver_not_converged = 1u << 6,       // a fixed-count solver ended above its residual bound
  deadline_missed = 1u << 7,            // a tick started after its deadline
  bad_sample = 1u << 8,                 // an input sample failed validation and was dropped
  unstable_step = 1u << 9,              // an explicit step longer than its stable limit was taken
  reduced_out_of_envelope = 1u << 10,   // a reduced model's state left its training envelope
  clock_went_backwards = 1u << 11,      // a sample's timestamp was not after the previous one
  pose_jump_rejected = 1u << 12,        // a pose moved faster than its limits and was dropped
  reduced_escalated = 1u << 13,         // a reduced ladder redid its step one rung up (larger basis or full order)
  reduced_error_over_bound = 1u << 14,  // a reduced model's estimated error passed its calibrated bound
};

/// A set of HealthFlag bits, raised by step-time code and read by the loop and displays.
class HealthFlags {
 public:
  constexpr void raise(HealthFlag flag) noexcept { bits_ |= static_cast<std::uint32_t>(flag); }
  constexpr void clear(HealthFlag flag) noexcept { bits_ &= ~static_cast<std::uint32_t>(flag); }
  constexpr void clear_all() noexcept { bits_ = 0; }
  constexpr bool has(HealthFlag flag) const noexcept { return (bits_ & static_cast<std::uint32_t>(flag)) != 0; }
  constexpr bool healthy() const noexcept { return bits_ == 0; }
  constexpr std::uint32_t bits() const noexcept { return bits_; }
  constexpr void merge(HealthFlags other) noexcept { bits_ |= other.bits_; }

 private:
  std::uint32_t bits_ = 0;
};

/// The flag's name in snake case, for logs and displays.
const char* health_flag_name(HealthFlag flag) noexcept;

}  // namespace nav
