#pragma once
// navview running alongside the demo station: a child process (the navview executable next
// to navstation's) that subscribes to the station's DDS topics and writes PNG composites
// (headless) into a folder; stopped with SIGTERM, on which it deletes its participant. Its
// output goes to a log file, never to navstation's own stdout/stderr.
#include <string>
#include <vector>

#include <sys/types.h>

#include "nav/core/error.hpp"

namespace navstation {

/// A running navview child process.
class NavviewProcess {
 public:
  /// Starts `navview` (next to this executable) with `args`, its output into `log_path`, or
  /// says why it cannot.
  static nav::Result<NavviewProcess> start(const std::vector<std::string>& args, const std::string& log_path);
  NavviewProcess(NavviewProcess&& other) noexcept : pid_(other.pid_) { other.pid_ = -1; }
  NavviewProcess& operator=(NavviewProcess&&) = delete;
  NavviewProcess(const NavviewProcess&) = delete;
  ~NavviewProcess() { stop(); }

  /// Sends SIGTERM and waits; navview's exit code (-1 when it was not running or died of a signal).
  int stop();

 private:
  explicit NavviewProcess(pid_t pid) : pid_(pid) {}
  pid_t pid_ = -1;
};

}  // namespace navstation
