#pragma once
// A program of this installation (an executable beside navstation: navdevice, navtool,
// navview) run as a child process, its output in a log file. The child gets SIGTERM should
// navstation die without stopping it, and is stopped (SIGTERM, then SIGKILL after a grace
// period) when navstation lets go of it: stopping the station stops its children.
#include <optional>
#include <string>
#include <vector>

#include <sys/types.h>

#include "nav/core/error.hpp"

namespace navstation {

/// A running child process.
class ChildProcess {
 public:
  /// Starts `program` (the executable of that name in navstation's own folder) with `args`,
  /// stdout and stderr into `log_path`, or says why it cannot.
  static nav::Result<ChildProcess> start(const std::string& program, const std::vector<std::string>& args,
                                         const std::string& log_path);
  ChildProcess(ChildProcess&& other) noexcept;
  ChildProcess& operator=(ChildProcess&&) = delete;
  ChildProcess(const ChildProcess&) = delete;
  ~ChildProcess() { stop(kStopGraceS); }

  const std::string& program() const { return program_; }
  const std::string& log_path() const { return log_path_; }
  pid_t pid() const { return pid_; }

  /// True once the child has ended (never blocks).
  bool ended();

  /// Waits up to `timeout_s` for the child to end: its exit code; -1 when a signal ended it;
  /// nothing when it still runs.
  std::optional<int> wait(double timeout_s);

  /// Sends SIGTERM, waits up to `grace_s`, then SIGKILL: its exit code, or -1 when it did not
  /// exit by itself (or was not running).
  int stop(double grace_s);

  /// What the child wrote so far.
  std::string log() const;

  static constexpr double kStopGraceS = 10.0;

 private:
  ChildProcess(std::string program, std::string log_path, pid_t pid)
      : program_(std::move(program)), log_path_(std::move(log_path)), pid_(pid) {}
  std::string program_, log_path_;
  pid_t pid_ = -1;
  std::optional<int> status_;  ///< waitpid's status once it ended
};

}  // namespace navstation
