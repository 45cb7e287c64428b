#pragma once
// The demo's other processes: the simulated patient (navdevice sim), the evaluation
// (navtool evaluate) and, for soak runs, a load on the host (navdevice load), children of `navstation --demo` on its
// scene and DDS domain, as a station engineer would run them by hand (README: the live station). The station itself
// runs in navstation's own process between start and finish_and_report.
#include <cstdint>
#include <optional>
#include <string>

#include "child_process.hpp"

namespace navstation {

/// What the demo's children run on.
struct DemoPlan {
  std::string scene_path;
  double seconds = 10.0;  ///< the station's run
  std::uint32_t domain_id = 0;
  std::string plot_path, json_path;  ///< the evaluation's error plot and figures (optional)
  std::string logs_dir;              ///< the children's logs
  double load_factor = 0.0;          ///< > 0: a load generator (navdevice load) at this factor of the scene's rates
};

/// The patient and the evaluation, running.
class DemoChildren {
 public:
  /// Starts the patient, waits until it has simulated its world and waits for a station, then
  /// starts the evaluation and the load, if any; an error names the child and ends with the
  /// tail of its log.
  static nav::Result<DemoChildren> start(const DemoPlan& plan);

  /// After the station's run: stops the load, the patient, then the evaluation (which then
  /// scores what it received) and prints its report; false when any failed.
  bool finish_and_report();

 private:
  DemoChildren(ChildProcess patient, ChildProcess evaluation, std::optional<ChildProcess> load)
      : patient_(std::move(patient)), evaluation_(std::move(evaluation)), load_(std::move(load)) {}
  ChildProcess patient_, evaluation_;
  std::optional<ChildProcess> load_;
};

}  // namespace navstation
