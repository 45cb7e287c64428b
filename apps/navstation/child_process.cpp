#include "child_process.hpp"

#include <chrono>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include <fcntl.h>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

namespace navstation {

nav::Result<ChildProcess> ChildProcess::start(const std::string& program, const std::vector<std::string>& args,
                                              const std::string& log_path) {
  std::error_code error;
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", error);
  if (error)
    return nav::Error{.message = "cannot find navstation's own folder: " + error.message(), .file = "/proc/self/exe"};
  const std::string path = (self.parent_path() / program).string();
  if (access(path.c_str(), X_OK) != 0)
    return nav::Error{.message = "cannot start " + program + ": " + std::strerror(errno), .file = path};
  std::vector<std::string> arguments{path};
  arguments.insert(arguments.end(), args.begin(), args.end());
  std::vector<char*> argv;
  for (std::string& a : arguments) argv.push_back(a.data());
  argv.push_back(nullptr);
  const int log = open(log_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (log < 0)
    return nav::Error{.message = std::string("cannot write the log of ") + program + ": " + std::strerror(errno),
                      .file = log_path};
  const pid_t parent = getpid();
  const pid_t pid = fork();
  if (pid == 0) {  // only async-signal-safe calls until exec
    prctl(PR_SET_PDEATHSIG, SIGTERM);
    if (getppid() != parent) _exit(127);  // the parent died before the request took hold
    dup2(log, STDOUT_FILENO);
    dup2(log, STDERR_FILENO);
    execv(argv[0], argv.data());
    _exit(127);
  }
  const int fork_error = errno;
  close(log);
  if (pid < 0)
    return nav::Error{.message = std::string("cannot start ") + program + ": " + std::strerror(fork_error),
                      .file = path};
  return ChildProcess(program, log_path, pid);
}

ChildProcess::ChildProcess(ChildProcess&& other) noexcept
    : program_(std::move(other.program_)),
      log_path_(std::move(other.log_path_)),
      pid_(other.pid_),
      status_(other.status_) {
  other.pid_ = -1;
}

bool ChildProcess::ended() {
  if (pid_ <= 0) return true;
  int status = 0;
  if (!status_ && waitpid(pid_, &status, WNOHANG) == pid_) status_ = status;
  return status_.has_value();
}

std::optional<int> ChildProcess::wait(double timeout_s) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  while (!ended()) {
    if (std::chrono::steady_clock::now() > deadline) return std::nullopt;
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  if (pid_ <= 0) return -1;
  return WIFEXITED(*status_) ? WEXITSTATUS(*status_) : -1;
}

int ChildProcess::stop(double grace_s) {
  if (pid_ <= 0) return -1;
  if (!ended()) kill(pid_, SIGTERM);
  std::optional<int> code = wait(grace_s);
  if (!code) {
    kill(pid_, SIGKILL);
    int status = 0;
    waitpid(pid_, &status, 0);
    code = -1;
  }
  pid_ = -1;
  return *code;
}

std::string ChildProcess::log() const {
  std::ifstream in(log_path_);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace navstation
