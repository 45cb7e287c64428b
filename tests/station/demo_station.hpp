#pragma once
// The demo station of the running-station tests (header-only: shared by the programs of
// tests/station): the demo scene, its liver and reduced loop, and its simulated world.
#include "nav/station/scene.hpp"
#include "nav/station/simulated_world.hpp"
#include "nav/station/station_loop.hpp"
#include "nav/station/station_run.hpp"
#include "scene_text.hpp"

namespace nav::testing {

/// The demo scene, its liver and loop, and its world of `duration_ns`.
struct DemoStation {
  station::Scene scene;
  station::StationLiver liver;
  OperatingLoopModel loop;
  station::SimulatedWorld world;
  explicit DemoStation(TimeNs duration_ns) {
    using namespace nav::station;
    scene = load_scene(example_scene_path("demo.yaml")).value();
    liver = make_station_liver(scene).value();
    const BreathingGeometry breathing;
    loop = make_station_loop(liver, scene, breathing, StationLoopSettings{}).value();
    WorldOptions options;
    options.duration_ns = duration_ns;
    world = simulate_world(liver, scene, breathing, options).value();
  }
};

}  // namespace nav::testing
