#pragma once
// navdevice plus: a PLUS recording played as the station's scanner and tracker (plus_device.cpp).
#include <string>
#include <vector>

#include "nav/core/error.hpp"
#include "nav/station/scene.hpp"
#include "nav/ultrasound/plus_sequence.hpp"

namespace navdevice {

/// The recording a PLUS device plays: `recording` when given, else the scene's (a scene of
/// devices.ultrasound kind plus), at the scene's pixel spacing when it gives one.
nav::Result<nav::ultrasound::PlusSequence> scene_recording(const nav::station::Scene& scene,
                                                           const std::string& recording);

/// Runs `navdevice plus` with its arguments (after the subcommand); returns the exit code.
int run_plus(const std::vector<std::string>& args);

}  // namespace navdevice
