#pragma once
// A station built from scene text (header-only: shared by the programs of tests/station that
// build edited scenes).
#include <string>
#include <utility>

#include "nav/station/station_build.hpp"
#include "scene_text.hpp"

namespace nav::testing {

/// The station that `text` declares, read as the demo scene's file (its relative paths resolve
/// beside it).
inline Result<station::BuiltStation> build_text(const std::string& text) {
  auto scene = station::parse_scene(text, example_scene_path("demo.yaml"));
  if (!scene.ok()) return scene.error();
  return station::build_station(std::move(scene).value());
}

}  // namespace nav::testing
