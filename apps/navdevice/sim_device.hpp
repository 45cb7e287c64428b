#pragma once
// navdevice sim: the simulated patient as a device process (sim_device.cpp).
#include <string>
#include <vector>

namespace navdevice {

/// Runs `navdevice sim` with its arguments (after the subcommand); returns the exit code.
int run_sim(const std::vector<std::string>& args);

}  // namespace navdevice
