#pragma once
// The sub-commands of navtool. Each takes the arguments after its own name and returns
// the process exit code: 0 ok, 2 bad input (with a message on stderr), 1 other failure.
#include <string>
#include <vector>

namespace navtool {

constexpr int exit_ok = 0;
constexpr int exit_failure = 1;
constexpr int exit_bad_input = 2;

/// navtool mesh info FILE [--unit mm|cm|m] [--json]
int mesh_info(const std::vector<std::string>& args);

/// navtool mesh make (--liver | --surface FILE [--unit U] | --labels FILE) --size H --out FILE.vtu
int mesh_make(const std::vector<std::string>& args);

/// navtool record --out FILE [--duration-s S] [--domain D] ... and navtool replay FILE
/// [--as-fast-as-possible] [--domain D] ...: args start with "record" or "replay".
int record_replay(const std::vector<std::string>& args);

}  // namespace navtool
