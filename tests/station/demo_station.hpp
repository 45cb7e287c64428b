#pragma once
// The demo station of the running-station tests (header-only: shared by the programs of
// tests/station): the demo scene, its liver and reduced loop, and its simulated world.
#include <functional>

#include "nav/station/scene.hpp"
#include "nav/station/simulated_world.hpp"
#include "nav/station/station_loop.hpp"
#include "nav/station/station_run.hpp"
#include "scene_text.hpp"

namespace nav::testing {

/// The demo scene (changed by `edit`, when given), its liver and loop, and its world of
/// `duration_ns` (`options` besides).
struct DemoStation {
  station::Scene scene;
  station::StationLiver liver;
  OperatingLoopModel loop;
  station::SimulatedWorld world;
  explicit DemoStation(TimeNs duration_ns, const std::function<void(station::Scene&)>& edit = {},
                       station::WorldOptions options = {}) {
    using namespace nav::station;
    scene = load_scene(example_scene_path("demo.yaml")).value();
    if (edit) edit(scene);
    liver = make_station_liver(scene).value();
    const BreathingGeometry breathing;
    loop = make_station_loop(liver, scene, breathing, StationLoopSettings{}).value();
    options.duration_ns = duration_ns;
    world = simulate_world(liver, scene, breathing, options).value();
  }
};

}  // namespace nav::testing
