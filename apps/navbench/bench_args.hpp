#pragma once
// The command line shared by the model benchmarks: --json FILE [--quick].
#include <optional>
#include <string>
#include <vector>

namespace navbench {

/// Where to write the records, and whether to run the short version (for CI).
struct BenchArgs {
  std::string json_path;
  bool quick = false;
};

/// Parses --json FILE [--quick]; prints `usage` to stderr and returns nullopt without --json.
std::optional<BenchArgs> parse_bench_args(const std::vector<std::string>& args, const char* usage);

}  // namespace navbench
