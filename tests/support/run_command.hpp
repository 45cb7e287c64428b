#pragma once
// Runs a shell command from a test and captures what it printed and its exit code, for
// tests that drive the project's executables as a user would.
#include <string>

namespace nav::testing {

/// What a finished command printed (the streams its redirections captured) and returned.
struct CommandRun {
  std::string output;
  int exit_code = -1;  ///< -1 if it could not start or did not exit normally
};

/// Runs `shell_command` through /bin/sh and reads its standard output to the end.
CommandRun run_command(const std::string& shell_command);

/// The path of an executable of this build (build/bin/<name>).
std::string executable_path(const std::string& name);

}  // namespace nav::testing
