// navbridge: the station joined to the tools of image-guided therapy.
//   navbridge igtl --scene FILE [--seconds S] [--domain D]
//       OpenIGTLink both ways, as the scene's openigtlink section says: a PlusServer's tracked
//       tools (TRANSFORM) and ultrasound (IMAGE) onto the scene's pose and frame topics, and
//       the station's surface, needle, tumour and health to every display connected to the
//       bridge (3D Slicer's OpenIGTLinkIF as a client). Prints a status line every second,
//       each refused message with its sender and field; stops on SIGINT and SIGTERM or after
//       --seconds. Exits 0 when stopped, 1 naming what failed, 2 on a usage error.
#include <algorithm>
#include <cstdio>
#include <limits>
#include <string>
#include <thread>
#include <vector>

#include "nav/bridge/igtl_bridge.hpp"
#include "nav/core/clock.hpp"
#include "nav/dds/stop_request.hpp"

namespace {

constexpr const char* kUsage = "usage: navbridge igtl --scene FILE [--seconds S] [--domain D]\n";

struct BridgeArgs {
  std::string scene_path;
  double seconds = 0.0;  ///< 0: until stopped
  long domain_id = -1;   ///< -1: the scene's
};

bool parse(const std::vector<std::string>& args, BridgeArgs& out) {
  if (args.empty() || args.front() != "igtl") return false;
  try {
    for (std::size_t i = 1; i < args.size(); ++i) {
      const bool has_value = i + 1 < args.size();
      if (args[i] == "--scene" && has_value)
        out.scene_path = args[++i];
      else if (args[i] == "--seconds" && has_value)
        out.seconds = std::stod(args[++i]);
      else if (args[i] == "--domain" && has_value)
        out.domain_id = std::stol(args[++i]);
      else
        return false;
    }
  } catch (const std::exception&) {
    return false;
  }
  return !out.scene_path.empty() && out.seconds >= 0.0 && out.domain_id >= -1 && out.domain_id <= 232;
}

int fail(const nav::Error& error) {
  std::fprintf(stderr, "navbridge igtl: %s\n", error.describe().c_str());
  return 1;
}

}  // namespace

int main(int argc, char** argv) {
  BridgeArgs args;
  if (!parse({argv + 1, argv + argc}, args)) {
    std::fprintf(stderr, "%s", kUsage);
    return 2;
  }
  nav::dds::install_stop_handlers();
  auto scene = nav::station::load_scene(args.scene_path);
  if (!scene) return fail(scene.error());
  if (args.domain_id >= 0) scene.value().topics.domain_id = static_cast<std::uint32_t>(args.domain_id);
  auto bridge = nav::bridge::IgtlBridge::open(scene.value());
  if (!bridge) return fail(bridge.error());
  nav::bridge::IgtlBridge& b = *bridge.value();
  const nav::station::OpenIgtlinkSettings& settings = *scene.value().openigtlink;
  std::printf("navbridge igtl: displays connect to %s:%d", settings.displays.host.c_str(), b.displays_port());
  if (settings.plus)
    std::printf("; %s %s:%d", settings.plus_connects ? "a PlusServer connects to" : "PlusServer at",
                settings.plus->host.c_str(), settings.plus_connects ? b.plus_port() : settings.plus->port);
  std::printf("; DDS domain %u\n", scene.value().topics.domain_id);
  std::fflush(stdout);

  std::thread running([&b] { b.run(); });
  nav::MonotonicClock clock;
  const nav::TimeNs start_ns = clock.now_ns();
  const nav::TimeNs end_ns = args.seconds > 0.0 ? start_ns + static_cast<nav::TimeNs>(args.seconds * 1e9)
                                                : std::numeric_limits<nav::TimeNs>::max();
  for (nav::TimeNs next_ns = start_ns + nav::kNsPerSecond; !nav::dds::stop_requested() && clock.now_ns() < end_ns;
       next_ns += nav::kNsPerSecond) {
    clock.sleep_until_ns(std::min(next_ns, end_ns));
    const nav::bridge::BridgeTotals t = b.totals();
    std::printf(
        "navbridge igtl: in %llu poses, %llu frames, %llu skipped, %llu refused; out %llu messages to %llu "
        "displays (%llu gone)\n",
        static_cast<unsigned long long>(t.poses_in), static_cast<unsigned long long>(t.frames_in),
        static_cast<unsigned long long>(t.skipped_in), static_cast<unsigned long long>(t.refused_in),
        static_cast<unsigned long long>(t.messages_out),
        static_cast<unsigned long long>(t.displays_connected - t.displays_dropped),
        static_cast<unsigned long long>(t.displays_dropped));
    std::fflush(stdout);
  }
  b.stop();
  running.join();
  std::printf("navbridge igtl: stopped\n");
  return 0;
}
