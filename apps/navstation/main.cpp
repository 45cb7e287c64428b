// navstation: the navigation station.
//   --scene FILE --check   loads the scene, builds the models it declares, prints their memory
//                          footprint, the liver's escalation ladder (when declared) and what the
//                          real-time setup would do here, and exits.
//   --scene FILE           runs the scene and its simulated world in this one process: the
//                          real-time loop and the I/O thread for --seconds (default 10), then
//                          prints the summary with the errors with and without assimilation
//                          (a replay of the same recording without ultrasound).
//   --scene FILE --live    runs the station alone on devices that are other processes on DDS
//                          (navdevice sim, ...): the real-time loop and the I/O thread for
//                          --seconds, then prints the summary of timing and what arrived; the
//                          evaluation against a simulated patient's truth is navtool evaluate.
//   --scene FILE --replay REC  runs the station on the poses and frames of a recorded session
//                          (navtool record) on a simulated clock, as fast as it computes, and
//                          prints the hash of its outputs: the same recording, the same bits.
//   --demo                 the live station on the demo scene (scenes/demo.yaml) with its
//                          simulated patient (navdevice sim) and its evaluation (navtool
//                          evaluate) as child processes (their logs in --logs DIR, default a
//                          temporary folder); stopping navstation stops them. All on DDS (the
//                          scene's topics.domain_id, or --domain D).
//   --load F               (--demo) a load on the host as well (navdevice load: F times the
//                          scene's device rates on topics of its own, on the I/O core): a soak
//                          run, e.g. --demo --seconds 3600 --load 4
//   --seconds S, --plot FILE.svg (the error over time), --json FILE (the summary's figures;
//                          with --live: start-up, resident memory, ticks and samples;
//                          with --demo: {"station": those, "evaluation": navtool evaluate's}),
//   --images DIR           runs navview alongside (headless), which writes PNG composites of
//                          the station's DDS topics (by the scene's topic names) into DIR
//                          (with the liver surface DIR/liver_surface.obj).
// Exit code 0, 1 with the error, 2 on a usage error.
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <optional>
#include <string>
#include <vector>

#include <unistd.h>

#include "demo_children.hpp"
#include "nav/core/kernel_isa.hpp"
#include "nav/core/text_file.hpp"
#include "nav/dds/stop_request.hpp"
#include "nav/station/realtime_thread.hpp"
#include "nav/station/scene.hpp"
#include "nav/station/session_replay.hpp"
#include "nav/station/station_build.hpp"
#include "nav/station/station_dds.hpp"
#include "nav/station/station_loop.hpp"
#include "nav/station/station_session.hpp"
#include "navview_beside.hpp"

namespace {

constexpr const char* kUsage =
    "usage: navstation --scene FILE --check\n"
    "       navstation (--demo [--logs DIR] [--load F] | --scene FILE) [--seconds S] [--domain D] [--plot FILE.svg] "
    "[--json FILE]\n"
    "                                                        [--images DIR]\n"
    "       navstation --scene FILE --live [--seconds S] [--domain D] [--images DIR]\n"
    "       navstation --scene FILE --replay REC.navrec\n";
constexpr int kExitError = 1;
constexpr int kExitUsage = 2;

/// The command line.
struct Arguments {
  std::string scene_path;
  bool check = false, demo = false, live = false;
  double seconds = 10.0;
  double load_factor = 0.0;  ///< --load F (--demo): a load generator at F x the scene's rates
  long domain_id = -1;       ///< -1: the scene's
  std::string plot_path, json_path, images_dir, replay_path, logs_dir;
};

void print_plan(const nav::station::Scene& scene) {
  const nav::station::StationSettings& s = scene.station;
  std::printf("station '%s': loop %.0f Hz, tissue %.0f Hz, display latency %.1f ms\n", s.name.c_str(), s.loop_rate_hz,
              s.tissue_rate_hz, s.display_latency_ms);
  std::printf("threads: real-time loop on core %d, I/O on core %d\n", s.realtime_core, s.io_core);
  const std::string_view isa = nav::kernel_isa_name(nav::resolve_kernel_isa(nav::KernelIsa::best));
  std::printf("lane kernels: %.*s (every instruction set gives the same bits)\n", static_cast<int>(isa.size()),
              isa.data());
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

/// The reduced liver's escalation ladder: its rungs and how it moves between them.
void print_ladder(const nav::station::LiverModels& liver) {
  if (!liver.ladder) return;
  const nav::ReducedLadderModel& ladder = *liver.ladder;
  const nav::ReducedLadderOptions& o = ladder.options();
  std::printf("liver escalation ladder: %d rungs; ", ladder.rung_count());
  if (!o.escalation_allowed) {
    std::printf("escalation not allowed (the indicator only raises its flag)\n");
  } else if (o.de_escalate_after_steps > 0) {
    std::printf(
        "escalation allowed after %d flagged step(s); steps down after %d steps inside ratio %.3g, residual %.3g\n",
        o.escalate_after_steps, o.de_escalate_after_steps, o.de_escalation_envelope_ratio, o.de_escalation_residual);
  } else {
    std::printf("escalation allowed after %d flagged step(s); never steps down\n", o.escalate_after_steps);
  }
  for (int k = 0; k < ladder.reduced_rung_count(); ++k) {
    const nav::ReducedModel& rung = ladder.reduced_rung(k);
    std::printf("  rung %d  reduced r = %d, %d sampled tetrahedra", k, rung.basis_size(), rung.sample_count());
    if (k + 1 < ladder.reduced_rung_count())
      std::printf(", transfer loss to rung %d %.1e", k + 1, ladder.transfer_loss(k));
    std::printf("\n");
  }
  if (ladder.has_full_order())
    std::printf("  rung %d  full order, %lld tetrahedra\n", ladder.reduced_rung_count(),
                static_cast<long long>(ladder.full_order().tet_count()));
}

int check_scene(nav::station::Scene scene) {
  print_plan(scene);
  if (const nav::Status runnable = nav::station::check_station_loop(scene); !runnable.ok()) {
    std::fprintf(stderr, "navstation: %s\n", runnable.error().describe().c_str());
    return kExitError;
  }
  auto built = nav::station::build_station(std::move(scene));
  if (!built.ok()) {
    std::fprintf(stderr, "navstation: %s\n", built.error().describe().c_str());
    return kExitError;
  }
  std::printf("memory footprint:\n%s", nav::station::format_footprint(built.value().footprint).c_str());
  print_ladder(built.value().models.liver);
  print_realtime(built.value().models.scene.station);
  return 0;
}

bool write_file(const std::string& path, const std::string& text) {
  const nav::Status written = nav::write_text_file(path, text);
  if (!written.ok()) std::fprintf(stderr, "navstation: %s\n", written.error().describe().c_str());
  return written.ok();
}

/// The whole text of `path`, or nothing (the reason printed).
std::optional<std::string> read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    std::fprintf(stderr, "navstation: %s: cannot be read\n", path.c_str());
    return std::nullopt;
  }
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

/// Runs the live station; its figures go to --json, or to `figures_json` when given (the demo's).
int run_live(const nav::station::Scene& scene, const Arguments& args, std::string* figures_json = nullptr) {
  print_plan(scene);
  std::printf("building the liver and its reduced loop, then running %.1f s on the devices of domain %u ...\n",
              args.seconds, scene.topics.domain_id);
  std::fflush(stdout);
  nav::dds::install_stop_handlers();  // SIGINT, SIGTERM: the run ends at its next tick and reports
  navstation::NavviewBeside navview(scene, args.images_dir, args.seconds);
  auto session = nav::station::run_live_session(
      scene, static_cast<nav::TimeNs>(args.seconds * 1e9),
      [&](const nav::station::DisplaySurface& surface) { return navview.start(surface); }, &nav::dds::g_stop_requested);
  const bool images = navview.stop_and_report();
  if (!session.ok()) {
    std::fprintf(stderr, "navstation: %s\n", session.error().describe().c_str());
    return kExitError;
  }
  std::printf("%s", nav::station::format_live_summary(scene, session.value()).c_str());
  if (figures_json != nullptr) *figures_json = nav::station::live_session_json(scene, session.value());
  const bool written = figures_json != nullptr || args.json_path.empty() ||
                       write_file(args.json_path, nav::station::live_session_json(scene, session.value()));
  return images && written ? 0 : kExitError;
}

/// The demo: the simulated patient and the evaluation as child processes, the live station here.
int run_demo(const nav::station::Scene& scene, const Arguments& args) {
  nav::dds::install_stop_handlers();
  const std::string logs_dir =
      args.logs_dir.empty()
          ? (std::filesystem::temp_directory_path() / ("navstation_demo." + std::to_string(getpid()))).string()
          : args.logs_dir;
  const std::string evaluation_json =
      args.json_path.empty() ? "" : (std::filesystem::path(logs_dir) / "evaluation.json").string();
  auto children = navstation::DemoChildren::start({NAV_STATION_DEMO_SCENE, args.seconds, scene.topics.domain_id,
                                                   args.plot_path, evaluation_json, logs_dir, args.load_factor});
  if (!children.ok()) {
    std::fprintf(stderr, "navstation: %s\n", children.error().describe().c_str());
    return kExitError;
  }
  std::string station_json;
  const int station = run_live(scene, args, &station_json);
  const bool evaluated = children.value().finish_and_report();
  if (evaluated && !args.plot_path.empty()) std::printf("error plot: %s\n", args.plot_path.c_str());
  bool written = true;
  if (!args.json_path.empty() && station == 0 && evaluated) {
    const std::optional<std::string> evaluation = read_file(evaluation_json);
    written = evaluation &&
              write_file(args.json_path, "{\"station\": " + station_json + ",\n\"evaluation\": " + *evaluation + "}\n");
  }
  return station == 0 && evaluated && written ? 0 : kExitError;
}

int run_replay(const nav::station::Scene& scene, const Arguments& args) {
  print_plan(scene);
  std::printf("building the liver and its reduced loop, then replaying %s ...\n", args.replay_path.c_str());
  std::fflush(stdout);
  auto replay = nav::station::replay_session(scene, args.replay_path);
  if (!replay.ok()) {
    std::fprintf(stderr, "navstation: %s\n", replay.error().describe().c_str());
    return kExitError;
  }
  std::printf("%s", nav::station::format_replay(scene, args.replay_path, replay.value()).c_str());
  return 0;
}

int run_scene(const nav::station::Scene& scene, const Arguments& args) {
  print_plan(scene);
  std::printf("building the liver, its reduced loop and the full-order world, then running %.1f s ...\n", args.seconds);
  std::fflush(stdout);
  nav::station::SessionOptions options;
  options.world.duration_ns = static_cast<nav::TimeNs>(args.seconds * 1e9);
  navstation::NavviewBeside navview(scene, args.images_dir, args.seconds);
  const auto start_navview = [&](const nav::station::DisplaySurface& surface) { return navview.start(surface); };
  auto session = nav::station::run_session(scene, options, start_navview);
  const bool images = navview.stop_and_report();
  if (!session.ok()) {
    std::fprintf(stderr, "navstation: %s\n", session.error().describe().c_str());
    return kExitError;
  }
  std::printf("%s", nav::station::format_summary(scene, session.value()).c_str());
  bool written = true;
  if (!args.plot_path.empty()) {
    written = write_file(args.plot_path,
                         nav::station::error_plot_svg("station '" + scene.station.name + "': tumour prediction error",
                                                      nav::station::error_series(session.value()))) &&
              written;
    if (written) std::printf("error plot: %s\n", args.plot_path.c_str());
  }
  if (!args.json_path.empty())
    written = write_file(args.json_path, nav::station::session_json(scene, session.value())) && written;
  written = written && images;
  return written ? 0 : kExitError;
}

/// Parses argv; false (after printing why) on a usage error.
bool parse(int argc, char** argv, Arguments& args) {
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const bool has_value = i + 1 < argc;
    if (arg == "--scene" && has_value) {
      args.scene_path = argv[++i];
    } else if (arg == "--check") {
      args.check = true;
    } else if (arg == "--replay" && has_value) {
      args.replay_path = argv[++i];
    } else if (arg == "--live") {
      args.live = true;
    } else if (arg == "--demo") {
      args.demo = true;
    } else if (arg == "--seconds" && has_value) {
      char* end = nullptr;
      args.seconds = std::strtod(argv[++i], &end);
      if (*end != '\0' || !(args.seconds > 0.0 && args.seconds <= 3600.0)) {
        std::fprintf(stderr, "navstation: --seconds takes a duration in (0, 3600]\n");
        return false;
      }
    } else if (arg == "--load" && has_value) {
      char* end = nullptr;
      args.load_factor = std::strtod(argv[++i], &end);
      if (*end != '\0' || !(args.load_factor > 0.0 && args.load_factor <= 100.0)) {
        std::fprintf(stderr, "navstation: --load takes a factor of the scene's device rates in (0, 100]\n");
        return false;
      }
    } else if (arg == "--domain" && has_value) {
      char* end = nullptr;
      args.domain_id = std::strtol(argv[++i], &end, 10);
      if (*end != '\0' || args.domain_id < 0 || args.domain_id > 232) {
        std::fprintf(stderr, "navstation: --domain takes a DDS domain id in 0..232\n");
        return false;
      }
    } else if (arg == "--plot" && has_value) {
      args.plot_path = argv[++i];
    } else if (arg == "--images" && has_value) {
      args.images_dir = argv[++i];
    } else if (arg == "--logs" && has_value) {
      args.logs_dir = argv[++i];
    } else if (arg == "--json" && has_value) {
      args.json_path = argv[++i];
    } else {
      std::fprintf(stderr, "navstation: unknown argument '%s'\n", arg.c_str());
      return false;
    }
  }
  if (args.demo == !args.scene_path.empty() || (args.check && args.demo)) {
    std::fprintf(stderr, "navstation: give --demo or --scene FILE\n");
    return false;
  }
  if (!args.replay_path.empty() && (args.demo || args.check || args.live || !args.plot_path.empty() ||
                                    !args.json_path.empty() || !args.images_dir.empty())) {
    std::fprintf(stderr, "navstation: --replay runs a --scene FILE alone on a recording\n");
    return false;
  }
  if (!args.demo && !args.live && args.replay_path.empty() && args.seconds > 600.0) {
    std::fprintf(stderr,
                 "navstation: a scene's world runs in this process for at most 600 s (--live or --demo: 3600)\n");
    return false;
  }
  if (args.load_factor > 0.0 && !args.demo) {
    std::fprintf(stderr, "navstation: --load runs the demo under load (--demo --load F)\n");
    return false;
  }
  if (!args.logs_dir.empty() && !args.demo) {
    std::fprintf(stderr, "navstation: --logs names the folder of the demo's child processes' logs\n");
    return false;
  }
  if (args.live && (args.demo || args.check || !args.plot_path.empty())) {
    std::fprintf(stderr,
                 "navstation: --live runs a --scene FILE alone (its evaluation is navtool evaluate; --json FILE: the "
                 "run's figures)\n");
    return false;
  }
  return true;
}

}  // namespace

int main(int argc, char** argv) {
  Arguments args;
  if (!parse(argc, argv, args)) {
    std::fprintf(stderr, "%s", kUsage);
    return kExitUsage;
  }
  auto scene = nav::station::load_scene(args.demo ? std::string(NAV_STATION_DEMO_SCENE) : args.scene_path);
  if (!scene.ok()) {
    std::fprintf(stderr, "navstation: %s\n", scene.error().describe().c_str());
    return kExitError;
  }
  if (args.check) return check_scene(std::move(scene).value());
  if (args.domain_id >= 0) scene.value().topics.domain_id = static_cast<std::uint32_t>(args.domain_id);
  if (!args.replay_path.empty()) return run_replay(scene.value(), args);
  if (args.demo) return run_demo(scene.value(), args);
  return args.live ? run_live(scene.value(), args) : run_scene(scene.value(), args);
}
