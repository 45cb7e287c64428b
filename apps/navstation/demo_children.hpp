#pragma once
// The demo's other processes: the simulated patient (navdevice sim) and the evaluation
// (navtool evaluate), children of `navstation --demo` on its scene and DDS domain, as a
// station engineer would run them by hand (README: the live station). The station itself runs
// in navstation's own process between start and finish_and_report.
#include <cstdint>
#include <string>

#include "child_process.hpp"

namespace navstation {

/// What the demo's children run on.
struct DemoPlan {
  std::string scene_path;
  double seconds = 10.0;           ///< the station's run
  std::uint32_t domain_id = 0;
  std::string plot_path, json_path;  ///< the evaluation's error plot and figures (optional)
  std::string logs_dir;            ///< the children's logs
};

/// The patient and the evaluation, running.
class DemoChildren {
 public:
  /// Starts the patient, waits until it has simulated its world and waits for a station, then
  /// starts the evaluation; an error names the child and ends with the tail of its log.
  static nav::Result<DemoChildren> start(const DemoPlan& plan);

  /// After the station's run: stops the patient, then the evaluation (which then scores what
  /// it received) and prints its report; false when either failed.
  bool finish_and_report();

 private:
  DemoChildren(ChildProcess patient, ChildProcess evaluation) : patient_(std::move(patient)), evaluation_(std::move(evaluation)) {}
  ChildProcess patient_, evaluation_;
};

}  // namespace navstation
