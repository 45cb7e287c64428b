// navbench: measurements of the station's plumbing, written as JSON for the records.
#include <cstdio>
#include <string>
#include <vector>

#include "dds_bench.hpp"

namespace {

constexpr const char* kUsage =
    "usage:\n"
    "  navbench dds --json FILE [--domain D] [--pose-samples N] [--frame-samples N]\n";

}  // namespace

int main(int argc, char** argv) {
  const std::vector<std::string> args(argv + 1, argv + argc);
  if (!args.empty()) {
    const std::vector<std::string> rest(args.begin() + 1, args.end());
    if (args[0] == "dds") return navbench::run_dds_bench(rest);
    if (args[0] == "dds-peer") return navbench::run_dds_peer(rest);
  }
  std::fputs(kUsage, stderr);
  return 2;
}
