#pragma once
// navdevice ndi: an NDI tracker (combined API, serial or TCP) as a device process (ndi_device.cpp).
#include <string>
#include <vector>

namespace navdevice {

/// Runs `navdevice ndi` with its arguments (after the subcommand); returns the exit code.
int run_ndi(const std::vector<std::string>& args);

}  // namespace navdevice
