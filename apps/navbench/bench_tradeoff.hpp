#pragma once
// navbench tradeoff: the speed/accuracy trade of the tissue rungs (full-order linear,
// corotational and StVK; reduced models of every basis source and force reduction over the
// basis size r and the cubature size) on liver meshes of several levels, with the error
// measured on held-out loads, as JSON records and a log-log Pareto plot.
#include <string>
#include <vector>

namespace navbench {

/// navbench tradeoff --json FILE --plot FILE [--quick]; returns the exit code.
int run_tradeoff_bench(const std::vector<std::string>& args);

}  // namespace navbench
