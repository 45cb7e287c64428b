// navbench: measurements of the station's plumbing and models, written as JSON for the records.
#include <cstdio>
#include <string>
#include <vector>

#include "bench_connective.hpp"
#include "bench_full.hpp"
#include "bench_needle.hpp"
#include "bench_tradeoff.hpp"
#include "dds_bench.hpp"

namespace {

constexpr const char* kUsage =
    "usage:\n"
    "  navbench dds --json FILE [--domain D] [--pose-samples N] [--frame-samples N] [--security DIR]\n"
    "  navbench full --json FILE [--quick]\n"
    "  navbench needle --json FILE [--quick]\n"
    "  navbench connective --json FILE [--quick]\n"
    "  navbench tradeoff --json FILE --plot FILE.svg [--quick]\n";

}  // namespace

int main(int argc, char** argv) {
  const std::vector<std::string> args(argv + 1, argv + argc);
  if (!args.empty()) {
    const std::vector<std::string> rest(args.begin() + 1, args.end());
    if (args[0] == "dds") return navbench::run_dds_bench(rest);
    if (args[0] == "dds-peer") return navbench::run_dds_peer(rest);
    if (args[0] == "full") return navbench::run_full_bench(rest);
    if (args[0] == "needle") return navbench::run_needle_bench(rest);
    if (args[0] == "connective") return navbench::run_connective_bench(rest);
    if (args[0] == "tradeoff") return navbench::run_tradeoff_bench(rest);
  }
  std::fputs(kUsage, stderr);
  return 2;
}
