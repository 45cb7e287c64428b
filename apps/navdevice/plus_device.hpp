#pragma once
// navdevice plus: a PLUS recording played as the station's scanner and tracker (plus_device.cpp).
#include <string>
#include <vector>

namespace navdevice {

/// Runs `navdevice plus` with its arguments (after the subcommand); returns the exit code.
int run_plus(const std::vector<std::string>& args);

}  // namespace navdevice
