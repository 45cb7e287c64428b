#include "nav/dds/health_text.hpp"

#include <cstdio>

#include "nav/core/health_names.hpp"
#include "nav/dds/sample_fault.hpp"

namespace nav::dds {

const char* station_mode_name(StationMode mode) noexcept {
  switch (mode) {
    case StationMode::starting:
      return "starting";
    case StationMode::running:
      return "running";
    case StationMode::degraded:
      return "DEGRADED";
    case StationMode::stopped:
      return "stopped";
  }
  return "in an unknown mode";
}

bool station_healthy(const StationHealth& health) noexcept {
  bool healthy = health.mode == StationMode::running && health.flags == 0;
  for (const std::uint32_t flags : health.input_flags) healthy = healthy && flags == 0;
  return healthy;
}

std::string input_state_words(const StationHealth& health, StationInput input) {
  const auto i = static_cast<std::size_t>(input);
  const std::string flags = health_flag_names(health.input_flags[i]);
  std::string text = std::string(station_input_name(input)) + ": ";
  const TimeNs age_ns = health.input_age_ns[i];
  if (age_ns < 0) return text + (flags.empty() ? "nothing received yet" : flags + ", nothing received yet");
  char age[32];
  if (age_ns < kNsPerSecond)
    std::snprintf(age, sizeof(age), "%lld ms ago", static_cast<long long>(age_ns / kNsPerMs));
  else if (age_ns < 120 * kNsPerSecond)
    std::snprintf(age, sizeof(age), "%.1f s ago", static_cast<double>(age_ns) / kNsPerSecond);
  else
    std::snprintf(age, sizeof(age), "%lld min ago", static_cast<long long>(age_ns / (60 * kNsPerSecond)));
  return text + (flags.empty() ? "healthy" : flags) + ", " + age;
}

std::string health_summary(const StationHealth& health) {
  const std::string flags = health_flag_names(health.flags);
  std::string text =
      std::string("station ") + station_mode_name(health.mode) + " | " + (flags.empty() ? "healthy" : flags);
  for (std::size_t i = 0; i < kStationInputCount; ++i)
    if (health.input_flags[i] != 0)
      text += std::string(" | ") + station_input_name(static_cast<StationInput>(i)) + ": " +
              health_flag_names(health.input_flags[i]);
  return text + " | dropped at the boundary: " + drops_by_reason(health.boundary);
}

}  // namespace nav::dds
