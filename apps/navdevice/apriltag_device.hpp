#pragma once
// navdevice apriltag: a camera watching AprilTag markers as the station's tracker (apriltag_device.cpp).
#include <string>
#include <vector>

namespace navdevice {

/// Runs `navdevice apriltag` with its arguments (after the subcommand); returns the exit code.
int run_apriltag(const std::vector<std::string>& args);

}  // namespace navdevice
