#pragma once
// navdevice plusserver: a PLUS recording served over OpenIGTLink as a PlusServer serves its
// tracker and scanner (plusserver_device.cpp).
#include <string>
#include <vector>

namespace navdevice {

/// Runs `navdevice plusserver` with its arguments (after the subcommand); returns the exit code.
int run_plusserver(const std::vector<std::string>& args);

}  // namespace navdevice
