#include "navview_args.hpp"

#include <cmath>
#include <optional>

namespace navview {
namespace {

/// "DEFAULT=NAME": the topic whose default name is DEFAULT takes NAME; false when DEFAULT is
/// no topic's default name or NAME is empty.
bool rename_topic(const std::string& value, nav::dds::TopicNames& names) {
  const std::size_t equals = value.find('=');
  if (equals == std::string::npos || equals + 1 == value.size()) return false;
  for (std::size_t t = 0; t < nav::dds::kTopicCount; ++t) {
    if (value.compare(0, equals, nav::dds::topic_name(static_cast<nav::dds::Topic>(t))) != 0) continue;
    names[t] = value.substr(equals + 1);
    return true;
  }
  return false;
}

}  // namespace

bool parse_args(const std::vector<std::string>& args, bool display_available, NavviewArgs& parsed) {
  parsed.headless = !display_available;
  std::optional<double> period_ms;
  double duration_s = 0.0;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& flag = args[i];
    if (flag == "--headless") {
      parsed.headless = true;
      continue;
    }
    if (i + 1 >= args.size()) return false;
    const std::string& value = args[++i];
    try {
      if (flag == "--out-dir")
        parsed.out_dir = value;
      else if (flag == "--period-ms")
        period_ms = std::stod(value);
      else if (flag == "--count")
        parsed.count = std::stoull(value);
      else if (flag == "--duration-s")
        duration_s = std::stod(value);
      else if (flag == "--surface-mesh")
        parsed.surface_mesh = value;
      else if (flag == "--panel-height")
        parsed.composite.panel_height_px = std::stoi(value);
      else if (flag == "--azimuth-deg")
        parsed.composite.view_azimuth_deg = std::stod(value);
      else if (flag == "--elevation-deg")
        parsed.composite.view_elevation_deg = std::stod(value);
      else if (flag == "--scene")
        parsed.scene_path = value;
      else if (flag == "--domain") {
        parsed.network.domain_id = static_cast<std::uint32_t>(std::stoul(value));
        parsed.domain_given = true;
      } else if (flag == "--local-address")
        parsed.network.local_address = value;
      else if (flag == "--peer")
        parsed.network.peer_addresses.push_back(value);
      else if (flag == "--topic") {
        if (!rename_topic(value, parsed.topic_names)) return false;
      } else if (flag == "--unit") {
        const auto unit = nav::parse_length_unit(value);
        if (!unit) return false;
        parsed.surface_mesh_unit = *unit;
      } else {
        return false;
      }
    } catch (const std::exception&) {
      return false;
    }
  }
  if (!period_ms) period_ms = parsed.headless ? 1000.0 : 33.0;
  if (!(*period_ms > 0.0) || duration_s < 0.0 || parsed.composite.panel_height_px < 16) return false;
  parsed.period_ns = static_cast<nav::TimeNs>(std::llround(*period_ms * 1e6));
  parsed.duration_ns = static_cast<nav::TimeNs>(std::llround(duration_s * 1e9));
  parsed.network.participant_name = "navview";
  // A scene says the network and the topics (a --domain beside it wins, as for navstation);
  // another network flag beside it would be silently overridden.
  const bool network_flags = parsed.network.local_address != nav::dds::NetworkConfig().local_address ||
                             !parsed.network.peer_addresses.empty() || parsed.topic_names != nav::dds::TopicNames{};
  return parsed.scene_path.empty() || !network_flags;
}

}  // namespace navview
