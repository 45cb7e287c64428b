#pragma once
// navview's command line.
#include <cstdint>
#include <string>
#include <vector>

#include "nav/core/clock.hpp"
#include "nav/core/units.hpp"
#include "nav/dds/network_config.hpp"
#include "nav/dds/topics.hpp"
#include "nav/view/composite.hpp"

namespace navview {

/// What navview was asked to do.
struct NavviewArgs {
  nav::dds::NetworkConfig network;
  nav::view::CompositeOptions composite;
  bool headless = false;        // default: true when $DISPLAY is unset
  std::string out_dir = ".";    // headless: where the PNG files go
  nav::TimeNs period_ns = 0;    // between two renders; default 1 s headless, 33 ms in a window
  std::uint64_t count = 0;      // stop after this many images (0: no limit)
  nav::TimeNs duration_ns = 0;  // stop after this long (0: until SIGINT/SIGTERM or the window closes)
  std::string surface_mesh;     // .obj with the surface's triangles (empty: draw vertices)
  nav::LengthUnit surface_mesh_unit = nav::LengthUnit::metre;
  nav::dds::TopicNames topic_names{};  // --topic DEFAULT=NAME renames a topic (empty: its default name)
  std::string scene_path;              // --scene: the scene's domain, topics, network and security (as a display)
  bool domain_given = false;           // --domain: wins over the scene's
};

inline constexpr const char* kUsage =
    "usage: navview [--headless] [--out-dir DIR] [--period-ms MS] [--count N] [--duration-s S]\n"
    "               [--surface-mesh FILE.obj [--unit mm|cm|m]] [--panel-height PX]\n"
    "               [--azimuth-deg A] [--elevation-deg E]\n"
    "               [--domain D] [--scene FILE | [--local-address A] [--peer A]...\n"
    "                [--topic DEFAULT=NAME]...]   (e.g. --topic nav/needle_state=or2/needle_state)\n";

/// Parses navview's arguments (without the program name); false on anything malformed.
/// `display_available` is whether $DISPLAY is set (it picks the default output).
bool parse_args(const std::vector<std::string>& args, bool display_available, NavviewArgs& parsed);

}  // namespace navview
