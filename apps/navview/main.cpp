// navview: the station's display. Subscribes to ultrasound frames, the needle, target
// predictions, the deformed surface and the station's health, and draws their newest values
// as one composite (nav/view/composite.hpp; the health as a band: mode, raised flags, samples
// dropped, and each input's state and age), into numbered PNG files (headless) or a window whose
// mouse and keys orbit and zoom the 3-D panel (x11_window.cpp). With a scene it also reads the tool
// poses, to place each frame where the tracked probe held it and draw the needle and the target
// over it (nav/station/image_placement.hpp).
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <memory>

#include "image_output.hpp"
#include "nav/dds/dds_node.hpp"
#include "nav/dds/stop_request.hpp"
#include "nav/mesh/load_mesh.hpp"
#include "nav/station/image_placement.hpp"
#include "nav/station/station_dds.hpp"
#include "nav/view/frame_overlay.hpp"
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

/// Where the newest frame lies, from the scene's probe and registration and the tool poses.
struct FramePlacement {
  explicit FramePlacement(nav::station::ImagePlacement p) : placement(std::move(p)) {}

  nav::station::ImagePlacement placement;
  std::unique_ptr<nav::dds::RingSink<nav::dds::ToolPose, 1024>> poses =
      std::make_unique<nav::dds::RingSink<nav::dds::ToolPose, 1024>>();
  nav::view::ImageFromModel image_from_model;

  /// Takes the poses that arrived; image_from_model for `frame`, or null when it cannot be placed.
  const nav::view::ImageFromModel* place(const nav::dds::UltrasoundFrame* frame) {
    for (nav::dds::ToolPose pose; poses->try_pop(pose);) placement.add_pose(pose);
    if (frame == nullptr) return nullptr;
    const auto model_from_image = placement.model_from_image(frame->source_time_ns);
    if (!model_from_image) return nullptr;
    const nav::RigidPose image_from = nav::inverse(*model_from_image);
    const Eigen::Matrix3d rotation = image_from.rotation.toRotationMatrix();
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) image_from_model.rotation[static_cast<std::size_t>(3 * r + c)] = rotation(r, c);
      image_from_model.translation_m[static_cast<std::size_t>(r)] = image_from.position_m[r];
    }
    return &image_from_model;
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
  std::unique_ptr<FramePlacement> placing;
  if (!args.scene_path.empty()) {
    auto scene = nav::station::load_scene(args.scene_path);
    if (!scene) return fail("scene", scene.error());
    auto placement = nav::station::ImagePlacement::create(scene.value());
    if (!placement) return fail("scene", placement.error());
    placing = std::make_unique<FramePlacement>(std::move(placement).value());
    if (const nav::Status subscribed = node.value()->subscribe(*placing->poses); !subscribed)
      return fail("DDS", subscribed.error());
  }

  nav::dds::install_stop_handlers();
  nav::view::CompositeOptions composite = args.composite;
  composite.interactive = !args.headless;
  nav::view::Composer composer(composite, std::move(triangles));
  nav::MonotonicClock clock;
  const nav::TimeNs start_ns = clock.now_ns();
  nav::TimeNs next_ns = start_ns;
  std::uint64_t shown = 0;
  while (!nav::dds::stop_requested() && !output.value()->closed()) {
    next_ns = std::max(next_ns + args.period_ns, clock.now_ns());  // a slow render skips periods
    clock.sleep_until_ns(next_ns);
    const bool view_changed = output.value()->poll_events(composer.view());
    if (output.value()->closed()) break;
    if (args.duration_ns > 0 && clock.now_ns() - start_ns >= args.duration_ns) break;
    if (!subscriptions.update() && !view_changed) continue;
    nav::view::DisplayInputs inputs = subscriptions.inputs();
    if (placing) inputs.image_from_model = placing->place(inputs.frame);
    if (const nav::Status shown_ok = output.value()->show(composer.render(inputs, subscriptions.health->latest()));
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
