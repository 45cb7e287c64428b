#pragma once
// The station's health in words, one line as every display shows it (navview's status band,
// the OpenIGTLink bridge's StationHealth string): its mode, its flags, each input in trouble,
// and what its boundary dropped.
#include <string>

#include "nav/dds/samples.hpp"

namespace nav::dds {

/// "starting", "running", "DEGRADED" or "stopped".
const char* station_mode_name(StationMode mode) noexcept;

/// Whether the station runs with no flag raised, its own or an input's.
bool station_healthy(const StationHealth& health) noexcept;

/// One input's state and the age of its newest good sample in words: "needle: healthy, 12 ms
/// ago", "ultrasound: stale_input, 1.4 s ago", "respiratory: nothing received yet".
std::string input_state_words(const StationHealth& health, StationInput input);

/// "station running | healthy | dropped at the boundary: none", with each input in trouble
/// after the station's flags ("needle: bad_sample stale_input").
std::string health_summary(const StationHealth& health);

}  // namespace nav::dds
