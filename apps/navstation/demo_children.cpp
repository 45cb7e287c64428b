#include "demo_children.hpp"

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <thread>

#include "nav/dds/stop_request.hpp"

namespace navstation {
namespace {

/// The patient's world is simulated first (minutes under the sanitizers): it may take this and
/// twice the run's length to be ready.
constexpr double kPatientReadyS = 300.0;
constexpr double kPatientEndS = 30.0;  ///< stopped after the station's run: its goodbye
constexpr double kEvaluationEndS = 60.0;
constexpr double kPatientExtraS = 1.0;  ///< the patient's world outlasts the station's run
constexpr const char* kPatientReady = "waiting up to";

/// The last lines of a child's log, for an error.
std::string log_tail(const ChildProcess& child) {
  const std::string log = child.log();
  std::size_t from = log.empty() ? 0 : log.size() - 1;  // past a final newline
  for (int lines = 0; lines < 6 && from > 0; ++lines) {
    const std::size_t newline = log.rfind('\n', from - 1);
    from = newline == std::string::npos ? 0 : newline;
  }
  return log.substr(from);
}

nav::Error failed(const ChildProcess& child, const std::string& what) {
  return nav::Error{.message = child.program() + " " + what + "; its log ends:\n" + log_tail(child),
                    .file = child.log_path()};
}

std::string seconds_text(double s) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3f", s);
  return text;
}

}  // namespace

nav::Result<DemoChildren> DemoChildren::start(const DemoPlan& plan) {
  std::error_code error;
  std::filesystem::create_directories(plan.logs_dir, error);
  if (error)
    return nav::Error{.message = "cannot make the folder of the demo's logs: " + error.message(),
                      .file = plan.logs_dir};
  const std::filesystem::path logs(plan.logs_dir);
  const std::string domain = std::to_string(plan.domain_id);
  const std::string wait_s = seconds_text(kPatientReadyS + 2.0 * plan.seconds);
  auto patient =
      ChildProcess::start("navdevice",
                          {"sim", "--scene", plan.scene_path, "--seconds", seconds_text(plan.seconds + kPatientExtraS),
                           "--domain", domain, "--wait-s", wait_s},
                          (logs / "patient.log").string());
  if (!patient.ok()) return patient.error();
  std::printf("navdevice sim (pid %d): the simulated patient, simulating its world first; log %s\n",
              patient.value().pid(), patient.value().log_path().c_str());
  std::fflush(stdout);
  const auto give_up =
      std::chrono::steady_clock::now() + std::chrono::duration<double>(kPatientReadyS + 2.0 * plan.seconds);
  while (patient.value().log().find(kPatientReady) == std::string::npos) {
    if (patient.value().ended()) return failed(patient.value(), "ended before it was ready");
    if (nav::dds::stop_requested()) return nav::Error{.message = "stopped before the patient was ready"};
    if (std::chrono::steady_clock::now() > give_up)
      return failed(patient.value(), "was not ready within " + wait_s + " s");
    std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  // The evaluation listens until it is stopped (after the patient's end): it scores on SIGTERM.
  std::vector<std::string> evaluate{"evaluate", "--scene", plan.scene_path, "--seconds", "3600", "--domain", domain};
  if (!plan.plot_path.empty()) evaluate.insert(evaluate.end(), {"--plot", plan.plot_path});
  if (!plan.json_path.empty()) evaluate.insert(evaluate.end(), {"--json", plan.json_path});
  auto evaluation = ChildProcess::start("navtool", evaluate, (logs / "evaluation.log").string());
  if (!evaluation.ok()) return evaluation.error();
  std::printf("navtool evaluate (pid %d): the predictions against the patient's truth; log %s\n",
              evaluation.value().pid(), evaluation.value().log_path().c_str());
  std::optional<ChildProcess> load;
  if (plan.load_factor > 0.0) {
    auto started = ChildProcess::start(
        "navdevice",
        {"load", "--scene", plan.scene_path, "--factor", seconds_text(plan.load_factor), "--domain", domain},
        (logs / "load.log").string());
    if (!started.ok()) return started.error();
    std::printf("navdevice load (pid %d): %.3g x the scene's device rates on the I/O core; log %s\n",
                started.value().pid(), plan.load_factor, started.value().log_path().c_str());
    load.emplace(std::move(started).value());
  }
  std::fflush(stdout);
  return DemoChildren(std::move(patient).value(), std::move(evaluation).value(), std::move(load));
}

bool DemoChildren::finish_and_report() {
  const int load_exit = load_ ? load_->stop(kPatientEndS) : 0;
  if (load_) {
    const std::string log = load_->log();
    const std::size_t last = log.rfind("navdevice load:");
    std::printf("%s", last == std::string::npos ? "navdevice load: printed nothing\n" : log.substr(last).c_str());
  }
  const int patient_exit = patient_.stop(kPatientEndS);  // its world outlasts the run
  const int evaluation_exit = evaluation_.stop(kEvaluationEndS);
  std::printf("\nthe evaluation (navtool evaluate):\n%s", evaluation_.log().c_str());
  if (patient_exit != 0) {
    std::fprintf(stderr, "navstation: %s\n",
                 failed(patient_, "failed (exit code " + std::to_string(patient_exit) + ")").describe().c_str());
    return false;
  }
  if (load_exit != 0) {
    std::fprintf(stderr, "navstation: %s\n",
                 failed(*load_, "failed (exit code " + std::to_string(load_exit) + ")").describe().c_str());
    return false;
  }
  if (evaluation_exit != 0) {
    std::fprintf(stderr, "navstation: the evaluation failed (exit code %d); its log is %s\n", evaluation_exit,
                 evaluation_.log_path().c_str());
    return false;
  }
  return true;
}

}  // namespace navstation
