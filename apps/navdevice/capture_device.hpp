#pragma once
// navdevice capture: a frame grabber, video or image sequence as the station's ultrasound
// scanner (capture_device.cpp).
#include <string>
#include <vector>

namespace navdevice {

/// Runs `navdevice capture` with its arguments (after the subcommand); returns the exit code.
int run_capture(const std::vector<std::string>& args);

}  // namespace navdevice
