// navview: the station's display. Subscribes to ultrasound frames, the needle, target
// predictions, the deformed surface and the station's health, and draws their newest values
// as one composite (nav/view/composite.hpp; the health as a band: mode, raised flags, samples
// dropped), into numbered PNG files (headless) or a window.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <memory>

#include "image_output.hpp"
#include "nav/dds/dds_node.hpp"
#include "nav/dds/stop_request.hpp"
#include "nav/mesh/load_mesh.hpp"
#include "nav/station/station_dds.hpp"
#include "navview_args.hpp"

namespace navview {
namespace {

using nav::dds::LatestSink;

/// The newest sample of each displayed stream, filled by the DDS listeners.
struct Subscriptions {
  std::unique_ptr<LatestSink<nav::dds::UltrasoundFrame>> frame =
      std::make_unique<LatestSink<nav::dds::UltrasoundFrame>>();
  std::unique_ptr<LatestSink<nav::dds::NeedleState>> needle = std::make_unique<LatestSink<nav::dds::NeedleState>>();
  std::unique_ptr<LatestSink<nav::dds::TargetPrediction>> prediction =
      std::make_unique<LatestSink<nav::dds::TargetPrediction>>();
  std::unique_ptr<LatestSink<nav::dds::DeformedSurface>> surface =
      std::make_unique<LatestSink<nav::dds::DeformedSurface>>();
  std::unique_ptr<LatestSink<nav::dds::StationHealth>> health = std::make_unique<LatestSink<nav::dds::StationHealth>>();

  nav::Status subscribe(nav::dds::DdsNode& node) {
    for (nav::Status status : {node.subscribe(*frame), node.subscribe(*needle), node.subscribe(*prediction),
                               node.subscribe(*surface), node.subscribe(*health)}) {
      if (!status) return status;
    }
    return nav::Done{};
  }

  /// Takes what arrived since the last call; true when anything did.
  bool update() {
    const bool fresh[] = {frame->update(), needle->update(), prediction->update(), surface->update(), health->update()};
    return fresh[0] || fresh[1] || fresh[2] || fresh[3] || fresh[4];
  }

  nav::view::DisplayInputs inputs() const {
    return {frame->latest(), needle->latest(), prediction->latest(), surface->latest()};
  }
};

int fail(const char* what, const nav::Error& error) {
  std::fprintf(stderr, "navview: %s: %s\n", what, error.describe().c_str());
  return EXIT_FAILURE;
}

int run(const NavviewArgs& args) {
  nav::view::SurfaceTriangles triangles;
  if (!args.surface_mesh.empty()) {
    auto mesh = nav::load_surface(args.surface_mesh, args.surface_mesh_unit);
    if (!mesh) return fail("surface mesh", mesh.error());
    triangles = std::move(mesh.value().triangles);
  }
  auto output = args.headless ? open_png_sequence(args.out_dir) : open_window("navview");
  if (!output) return fail("output", output.error());
  nav::dds::TopicQosOptions qos;
  qos.names = args.topic_names;
  nav::dds::NetworkConfig network = args.network;
  if (!args.scene_path.empty()) {
    auto scene = nav::station::scene_dds(args.scene_path, nav::station::Role::display);
    if (!scene) return fail("scene", scene.error());
    network = scene.value().network;
    network.participant_name = args.network.participant_name;
    if (args.domain_given) network.domain_id = args.network.domain_id;
    qos.names = scene.value().names;
  }
  auto node = nav::dds::DdsNode::create(network, qos);
  if (!node) return fail("DDS", node.error());
  Subscriptions subscriptions;
  if (const nav::Status subscribed = subscriptions.subscribe(*node.value()); !subscribed)
    return fail("DDS", subscribed.error());

  nav::dds::install_stop_handlers();
  nav::view::Composer composer(args.composite, std::move(triangles));
  nav::MonotonicClock clock;
  const nav::TimeNs start_ns = clock.now_ns();
  nav::TimeNs next_ns = start_ns;
  std::uint64_t shown = 0;
  while (!nav::dds::stop_requested() && !output.value()->closed()) {
    next_ns = std::max(next_ns + args.period_ns, clock.now_ns());  // a slow render skips periods
    clock.sleep_until_ns(next_ns);
    output.value()->poll_events();
    if (args.duration_ns > 0 && clock.now_ns() - start_ns >= args.duration_ns) break;
    if (!subscriptions.update()) continue;
    if (const nav::Status shown_ok =
            output.value()->show(composer.render(subscriptions.inputs(), subscriptions.health->latest()));
        !shown_ok) {
      return fail("output", shown_ok.error());
    }
    if (args.count > 0 && ++shown >= args.count) break;
  }
  return EXIT_SUCCESS;
}

}  // namespace
}  // namespace navview

int main(int argc, char** argv) {
  const std::vector<std::string> args(argv + 1, argv + argc);
  navview::NavviewArgs parsed;
  if (!navview::parse_args(args, std::getenv("DISPLAY") != nullptr, parsed)) {
    std::fputs(navview::kUsage, stderr);
    return 2;
  }
  return navview::run(parsed);
}
