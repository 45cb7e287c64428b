#include "latency_stats.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace navbench {
namespace {

/// The nearest-rank `fraction` quantile of sorted `values`, in microseconds.
double quantile_us(const std::vector<nav::TimeNs>& sorted, double fraction) {
  const auto rank = static_cast<std::size_t>(std::ceil(fraction * static_cast<double>(sorted.size())));
  return static_cast<double>(sorted[std::clamp<std::size_t>(rank, 1, sorted.size()) - 1]) / 1e3;
}

}  // namespace

void summarize_latencies(std::vector<nav::TimeNs>& latencies_ns, LatencyReport& report) {
  report.received = latencies_ns.size();
  if (latencies_ns.empty()) return;
  std::sort(latencies_ns.begin(), latencies_ns.end());
  report.median_us = quantile_us(latencies_ns, 0.5);
  report.p99_us = quantile_us(latencies_ns, 0.99);
  report.p999_us = quantile_us(latencies_ns, 0.999);
  report.max_us = static_cast<double>(latencies_ns.back()) / 1e3;
}

Json to_json(const LatencyReport& report) {
  return {{"name", report.name},         {"sent", report.sent},
          {"received", report.received}, {"median_us", report.median_us},
          {"p99_us", report.p99_us},     {"p999_us", report.p999_us},
          {"max_us", report.max_us},     {"throughput_mb_per_s", report.throughput_mb_per_s}};
}

std::string to_text(const LatencyReport& report) {
  char text[512];
  std::snprintf(text, sizeof(text), "%-52s %6llu/%-6llu median %8.1f us  p99 %8.1f us  p99.9 %8.1f us  max %8.1f us",
                report.name.c_str(), static_cast<unsigned long long>(report.received),
                static_cast<unsigned long long>(report.sent), report.median_us, report.p99_us, report.p999_us,
                report.max_us);
  std::string line = text;
  if (report.throughput_mb_per_s > 0.0) {
    std::snprintf(text, sizeof(text), "  %8.1f MB/s", report.throughput_mb_per_s);
    line += text;
  }
  return line;
}

}  // namespace navbench
