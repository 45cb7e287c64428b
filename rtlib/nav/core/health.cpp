#include "nav/core/health.hpp"
#include "nav/core/health_names.hpp"

namespace nav {

const char* health_flag_name(HealthFlag flag) noexcept {
  switch (flag) {
    case HealthFlag::non_finite_state:
      return "non_finite_state";
    case HealthFlag::inverted_element:
      return "inverted_element";
    case HealthFlag::stale_input:
      return "stale_input";
    case HealthFlag::missing_input:
      return "missing_input";
    case HealthFlag::pool_full:
      return "pool_full";
    case HealthFlag::buffer_overrun:
      return "buffer_overrun";
    case HealthFlag::solver_not_converged:
      return "solver_not_converged";
    case HealthFlag::deadline_missed:
      return "deadline_missed";
    case HealthFlag::bad_sample:
      return "bad_sample";
    case HealthFlag::unstable_step:
      return "unstable_step";
    case HealthFlag::reduced_out_of_envelope:
      return "reduced_out_of_envelope";
    case HealthFlag::clock_went_backwards:
      return "clock_went_backwards";
    case HealthFlag::pose_jump_rejected:
      return "pose_jump_rejected";
    case HealthFlag::reduced_escalated:
      return "reduced_escalated";
    case HealthFlag::reduced_error_over_bound:
      return "reduced_error_over_bound";
  }
  return "unknown";
}

std::string health_flag_names(std::uint32_t bits) {
  std::string names;
  for (std::uint32_t bit = 1; bit != 0; bit <<= 1)
    if ((bits & bit) != 0)
      names += std::string(names.empty() ? "" : " ") + health_flag_name(static_cast<HealthFlag>(bit));
  return names;
}

}  // namespace nav
