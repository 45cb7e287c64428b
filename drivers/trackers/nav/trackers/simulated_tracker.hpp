#pragma once
// A simulated tracker: scripted tool trajectories measured at a fixed rate, with seeded
// Gaussian noise on position and orientation, random dropouts (the tool reported missing)
// and a fixed latency between measurement and delivery. Same seed, same samples.
#include <cstdint>
#include <random>
#include <vector>

#include "nav/trackers/tracker_sample.hpp"
#include "nav/trackers/trajectory.hpp"

namespace nav::trackers {

/// One simulated tool.
struct SimulatedTool {
  std::uint32_t tool_id = 0;
  Trajectory trajectory;
  double dropout_probability = 0.0;  // per measurement
};

/// The simulated device's settings.
struct SimulatedTrackerConfig {
  std::vector<SimulatedTool> tools;
  TimeNs period_ns = kNsPerSecond / 60;
  TimeNs latency_ns = 0;            // from measurement to delivery
  double position_noise_m = 0.0;    // per axis, standard deviation
  double rotation_noise_rad = 0.0;  // per axis of a small rotation, standard deviation
  std::uint64_t seed = 1;
};

/// Produces the measurements of a simulated tracker as time passes.
class SimulatedTracker {
 public:
  explicit SimulatedTracker(SimulatedTrackerConfig config);
  /// Appends every measurement delivered by `now_ns` (measured at k * period, delivered at
  /// k * period + latency), one sample per tool and measurement; returns how many.
  std::size_t poll(TimeNs now_ns, std::vector<TrackerSample>& out);
  /// The noiseless pose of tool `index` at `time_ns` (the truth).
  TrackerSample truth(std::size_t index, TimeNs time_ns) const;

 private:
  SimulatedTrackerConfig config_;
  std::mt19937_64 rng_;
  std::uint32_t next_frame_ = 0;
};

}  // namespace nav::trackers
