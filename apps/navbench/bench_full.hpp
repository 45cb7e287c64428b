#pragma once
// navbench full: step time and error against the neo-Hookean reference of every tissue model,
// on liver meshes of about 1k, 5k and 22k tetrahedra, as JSON records and an SVG plot.
#include <string>
#include <vector>

namespace navbench {

/// navbench full --json FILE [--quick]; returns the exit code.
int run_full_bench(const std::vector<std::string>& args);

}  // namespace navbench
