#pragma once
// The command line shared by the model benchmarks: --json FILE [--quick].
#include <cstdio>
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

/// Opens an output file of a benchmark for writing; on failure says which file and why on
/// stderr and returns nullptr.
std::FILE* open_bench_output(const std::string& path);

}  // namespace navbench
