#pragma once
// navdevice load: a load on the station's host for soak runs (load_device.cpp).
#include <string>
#include <vector>

namespace navdevice {

/// Runs `navdevice load` with its arguments (after the subcommand); returns the exit code.
int run_load(const std::vector<std::string>& args);

}  // namespace navdevice
