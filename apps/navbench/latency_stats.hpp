#pragma once
// Latency figures of one benchmark run: order statistics of the measured one-way
// latencies, the throughput, and their JSON form.
#include <cstdint>
#include <string>
#include <vector>

#include "bench_json.hpp"
#include "nav/core/clock.hpp"

namespace navbench {

/// What one benchmark measured: name, counts, latency order statistics (microseconds)
/// and, for bulk data, the received throughput.
struct LatencyReport {
  std::string name;
  std::uint64_t sent = 0;
  std::uint64_t received = 0;
  double median_us = 0.0;
  double p99_us = 0.0;
  double p999_us = 0.0;
  double max_us = 0.0;
  double throughput_mb_per_s = 0.0;  // 0 when not measured
};

/// Fills the latency fields of `report` from `latencies_ns` (sorted in place; nearest rank).
void summarize_latencies(std::vector<nav::TimeNs>& latencies_ns, LatencyReport& report);

/// One JSON object, keys as in LatencyReport.
Json to_json(const LatencyReport& report);

/// One line for the console.
std::string to_text(const LatencyReport& report);

}  // namespace navbench
