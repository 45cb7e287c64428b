#pragma once
// The times of a benchmark's calls one by one, reported as their median and 99th percentile:
// the median is what toolchain/floor sets against the floor's median, free of the host's
// interruptions that Google Benchmark's mean over the iterations carries.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <string>
#include <vector>

namespace nav::bench {

/// Runs `call` once, appends its time in microseconds to `us` and returns it in seconds.
template <class Call>
double time_call(std::vector<double>& us, Call&& call) {
  const auto start = std::chrono::steady_clock::now();
  call();
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  us.push_back(seconds * 1e6);
  return seconds;
}

/// Sorts `us` and sets the counters `name`_us_median and `name`_us_p99.
inline void report_quantiles(benchmark::State& state, const std::string& name, std::vector<double>& us) {
  if (us.empty()) return;
  std::sort(us.begin(), us.end());
  state.counters[name + "_us_median"] = us[us.size() / 2];
  state.counters[name + "_us_p99"] = us[std::min(us.size() - 1, (us.size() * 99) / 100)];
}

}  // namespace nav::bench
