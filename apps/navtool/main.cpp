// navtool: offline tools around the library (mesh inspection and meshing for now).
#include <cstdio>
#include <string>
#include <vector>

#include "commands.hpp"

namespace {

constexpr const char* kUsage =
    "usage:\n"
    "  navtool mesh info FILE [--unit mm|cm|m] [--json]\n"
    "  navtool mesh make (--liver | --surface FILE [--unit mm|cm|m] | --labels FILE) --size H_M --out FILE.vtu\n"
    "  navtool record --out FILE [--duration-s S] [--domain D] [--local-address A] [--peer A]...\n"
    "  navtool replay FILE [--as-fast-as-possible] [--domain D] [--local-address A] [--peer A]...\n";

}  // namespace

int main(int argc, char** argv) {
  const std::vector<std::string> args(argv + 1, argv + argc);
  if (args.size() >= 2 && args[0] == "mesh") {
    const std::vector<std::string> rest(args.begin() + 2, args.end());
    if (args[1] == "info") return navtool::mesh_info(rest);
    if (args[1] == "make") return navtool::mesh_make(rest);
  }
  if (!args.empty() && (args[0] == "record" || args[0] == "replay")) return navtool::record_replay(args);
  std::fputs(kUsage, stderr);
  return navtool::exit_bad_input;
}
