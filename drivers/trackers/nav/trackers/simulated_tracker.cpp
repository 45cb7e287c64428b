#include "nav/trackers/simulated_tracker.hpp"

#include <cmath>

namespace nav::trackers {
namespace {

/// `q` (w x y z) turned by the small rotation vector `v`: q * exp(v / 2), normalised.
std::array<double, 4> perturb(const std::array<double, 4>& q, const std::array<double, 3>& v) {
  const double angle = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  const double s = angle > 0.0 ? std::sin(0.5 * angle) / angle : 0.5;
  const std::array<double, 4> d{std::cos(0.5 * angle), s * v[0], s * v[1], s * v[2]};
  std::array<double, 4> r{
      q[0] * d[0] - q[1] * d[1] - q[2] * d[2] - q[3] * d[3], q[0] * d[1] + q[1] * d[0] + q[2] * d[3] - q[3] * d[2],
      q[0] * d[2] - q[1] * d[3] + q[2] * d[0] + q[3] * d[1], q[0] * d[3] + q[1] * d[2] - q[2] * d[1] + q[3] * d[0]};
  const double norm = std::sqrt(r[0] * r[0] + r[1] * r[1] + r[2] * r[2] + r[3] * r[3]);
  for (double& c : r) c /= norm;
  return r;
}

}  // namespace

SimulatedTracker::SimulatedTracker(SimulatedTrackerConfig config) : config_(std::move(config)), rng_(config_.seed) {}

TrackerSample SimulatedTracker::truth(std::size_t index, TimeNs time_ns) const {
  TrackerSample sample;
  sample.tool_id = config_.tools[index].tool_id;
  sample.measured_time_ns = time_ns;
  sample.state = ToolState::ok;
  config_.tools[index].trajectory.at(time_ns, sample.position_m, sample.orientation_wxyz);
  return sample;
}

std::size_t SimulatedTracker::poll(TimeNs now_ns, std::vector<TrackerSample>& out) {
  std::normal_distribution<double> position_noise(0.0, config_.position_noise_m);
  std::normal_distribution<double> rotation_noise(0.0, config_.rotation_noise_rad);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::size_t delivered = 0;
  while (static_cast<TimeNs>(next_frame_) * config_.period_ns + config_.latency_ns <= now_ns) {
    const TimeNs measured_ns = static_cast<TimeNs>(next_frame_) * config_.period_ns;
    for (std::size_t i = 0; i < config_.tools.size(); ++i) {
      TrackerSample sample = truth(i, measured_ns);
      sample.frame_number = next_frame_;
      // Draw every random number whatever the outcome, so that one tool's dropouts do not
      // shift the other tools' noise.
      const bool dropped = uniform(rng_) < config_.tools[i].dropout_probability;
      const std::array<double, 3> dp{position_noise(rng_), position_noise(rng_), position_noise(rng_)};
      const std::array<double, 3> dr{rotation_noise(rng_), rotation_noise(rng_), rotation_noise(rng_)};
      if (dropped) {
        sample.state = ToolState::missing;
      } else {
        for (int k = 0; k < 3; ++k) sample.position_m[k] += dp[k];
        sample.orientation_wxyz = perturb(sample.orientation_wxyz, dr);
      }
      out.push_back(sample);
      ++delivered;
    }
    ++next_frame_;
  }
  return delivered;
}

}  // namespace nav::trackers
