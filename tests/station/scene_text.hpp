#pragma once
// The scenes of the station tests (header-only: shared by the programs of tests/station):
// the example scenes of apps/navstation/scenes, their text, and edits that change one line.
#include <gtest/gtest.h>

#include <string>

#include "support/test_data.hpp"

namespace nav::testing {

/// Path of the example scene apps/navstation/scenes/<name>.
inline std::string example_scene_path(const std::string& name) {
  return test_data_path("../../apps/navstation/scenes/" + name);
}

/// The text of the demo scene.
inline const std::string& demo_text() {
  static const std::string text = file_text(example_scene_path("demo.yaml"));
  return text;
}

/// The demo scene's text to be written elsewhere: its URDF by absolute path.
inline std::string movable_demo_text() {
  const std::string urdf = "urdf: ../../../calibration/urdf/station.urdf";
  const std::string text = demo_text();
  const std::size_t at = text.find(urdf);
  EXPECT_NE(at, std::string::npos) << "the demo scene has no '" << urdf << "'";
  if (at == std::string::npos) return text;
  return text.substr(0, at) + "urdf: " + example_scene_path("../../../calibration/urdf/station.urdf") +
         text.substr(at + urdf.size());
}

/// `text` with its first occurrence of `from` replaced by `to` (fails the test if absent).
inline std::string edited(const std::string& text, const std::string& from, const std::string& to) {
  const std::size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << "the scene has no '" << from << "'";
  if (at == std::string::npos) return text;
  return text.substr(0, at) + to + text.substr(at + from.size());
}

/// 1-based line of the first occurrence of `needle` in `text` (0 if absent).
inline int line_of(const std::string& text, const std::string& needle) {
  const std::size_t at = text.find(needle);
  if (at == std::string::npos) return 0;
  int line = 1;
  for (std::size_t i = 0; i < at; ++i) line += text[i] == '\n' ? 1 : 0;
  return line;
}

}  // namespace nav::testing
