// navstation: the navigation station. `--scene FILE --check` loads the scene, builds the
// models it declares, prints their memory footprint and what the real-time setup would do
// on this machine, and exits (0, or 1 with the error).
#include <cstdio>
#include <string>

#include "nav/station/realtime_thread.hpp"
#include "nav/station/scene.hpp"
#include "nav/station/station_build.hpp"

namespace {

constexpr const char* kUsage = "usage: navstation --scene FILE --check\n";
constexpr int kExitError = 1;
constexpr int kExitUsage = 2;

void print_plan(const nav::station::Scene& scene) {
  const nav::station::StationSettings& s = scene.station;
  std::printf("station '%s': loop %.0f Hz, tissue %.0f Hz, display latency %.1f ms\n", s.name.c_str(), s.loop_rate_hz,
              s.tissue_rate_hz, s.display_latency_ms);
  std::printf("threads: real-time loop on core %d, I/O on core %d\n", s.realtime_core, s.io_core);
}

void print_realtime(const nav::station::StationSettings& s) {
  const nav::station::RealtimePlan plan{s.realtime_core, s.realtime_priority, s.lock_memory};
  std::printf("real-time setup (probed on a short-lived thread):\n");
  bool all_applied = true;
  for (const nav::station::SetupStep& step : nav::station::probe_realtime_setup(plan)) {
    std::printf("  %-12s %-14s %s\n", step.name.c_str(), nav::station::outcome_name(step.outcome), step.detail.c_str());
    all_applied = all_applied && step.outcome == nav::station::SetupOutcome::applied;
  }
  std::printf(all_applied ? "the station would run with its full real-time setup\n"
                          : "the station would run anyway, without what was refused\n");
}

}  // namespace

int main(int argc, char** argv) {
  std::string scene_path;
  bool check = false;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    if (arg == "--scene" && i + 1 < argc) {
      scene_path = argv[++i];
    } else if (arg == "--check") {
      check = true;
    } else {
      std::fprintf(stderr, "navstation: unknown argument '%s'\n%s", arg.c_str(), kUsage);
      return kExitUsage;
    }
  }
  if (scene_path.empty() || !check) {
    std::fprintf(stderr, "%s", kUsage);
    return kExitUsage;
  }
  auto scene = nav::station::load_scene(scene_path);
  if (!scene.ok()) {
    std::fprintf(stderr, "navstation: %s\n", scene.error().describe().c_str());
    return kExitError;
  }
  print_plan(scene.value());
  auto built = nav::station::build_station(std::move(scene).value());
  if (!built.ok()) {
    std::fprintf(stderr, "navstation: %s\n", built.error().describe().c_str());
    return kExitError;
  }
  std::printf("memory footprint:\n%s", nav::station::format_footprint(built.value().footprint).c_str());
  print_realtime(built.value().models.scene.station);
  return 0;
}
