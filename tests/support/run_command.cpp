#include "support/run_command.hpp"

#include <sys/wait.h>

#include <array>
#include <cstdio>

namespace nav::testing {

CommandRun run_command(const std::string& shell_command) {
  CommandRun run;
  FILE* pipe = popen(shell_command.c_str(), "r");
  if (pipe == nullptr) return run;
  std::array<char, 4096> buffer{};
  std::size_t count = 0;
  while ((count = std::fread(buffer.data(), 1, buffer.size(), pipe)) > 0) run.output.append(buffer.data(), count);
  const int status = pclose(pipe);
  run.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  return run;
}

std::string executable_path(const std::string& name) { return std::string(NAV_BIN_DIR) + "/" + name; }

}  // namespace nav::testing
