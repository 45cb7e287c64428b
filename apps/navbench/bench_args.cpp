#include "bench_args.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>

namespace navbench {

std::optional<BenchArgs> parse_bench_args(const std::vector<std::string>& args, const char* usage) {
  BenchArgs parsed;
  for (std::size_t k = 0; k < args.size(); ++k) {
    if (args[k] == "--json" && k + 1 < args.size())
      parsed.json_path = args[++k];
    else if (args[k] == "--quick")
      parsed.quick = true;
  }
  if (parsed.json_path.empty()) {
    std::fputs(usage, stderr);
    return std::nullopt;
  }
  return parsed;
}

std::FILE* open_bench_output(const std::string& path) {
  std::FILE* file = std::fopen(path.c_str(), "w");
  if (!file) std::fprintf(stderr, "navbench: cannot write %s: %s\n", path.c_str(), std::strerror(errno));
  return file;
}

}  // namespace navbench
