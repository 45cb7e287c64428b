#pragma once
// navbench connective: step time of the frame-based connective tissue against its number of
// frames and integration points, and what two ligaments cost a liver scene against the same
// liver held by fixed nodes (step time, displacement difference, stability of the coupling),
// as JSON records.
#include <string>
#include <vector>

namespace navbench {

/// navbench connective --json FILE [--quick]; returns the exit code.
int run_connective_bench(const std::vector<std::string>& args);

}  // namespace navbench
